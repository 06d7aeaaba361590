#include <catch2/catch.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <random>

#include "hullpose/common/lcm_wire.hpp"
#include "rig_fixtures.hpp"

using namespace hullpose;
using hullpose::testing::encode;

namespace {
void put_i32(std::vector<uint8_t>& b, size_t at, int32_t v) {
  for (int k = 0; k < 4; ++k) b[at + static_cast<size_t>(k)] = static_cast<uint8_t>(static_cast<uint32_t>(v) >> (24 - 8 * k));
}
template <typename F>
void check_rejects_truncation(const std::vector<uint8_t>& b, F ok) {
  for (size_t n = 0; n < b.size(); ++n) CHECK_FALSE(ok(b.data(), n));
  auto longer = b;
  longer.push_back(0);
  CHECK_FALSE(ok(longer.data(), longer.size()));
}
}  // namespace

TEST_CASE("wire checks accept encoded messages and reject truncations and hostile lengths") {
  const Rig rig = testing::make_rig(1);
  auto sil = encode(testing::make_silhouette(rig, 0, 4, 1000));
  CHECK(wire::silhouette_ok(sil.data(), sil.size()));
  check_rejects_truncation(sil, wire::silhouette_ok);
  for (int32_t v : {0, -1, 1 << 30}) {
    auto b = sil;
    put_i32(b, 16, v);  // rig_id length
    CHECK_FALSE(wire::silhouette_ok(b.data(), b.size()));
  }
  const size_t payload_at = 16 + 4 + 5 + 4 + 8 + 8 + 24 + 1;
  for (int32_t v : {-1, -100, 0x7fffffff, 5}) {
    auto b = sil;
    put_i32(b, payload_at, v);
    CHECK_FALSE(wire::silhouette_ok(b.data(), b.size()));
  }

  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  auto tb = encode(t);
  CHECK(wire::trigger_ok(tb.data(), tb.size()));
  check_rejects_truncation(tb, wire::trigger_ok);

  hullpose_msg::skeleton_t s{};
  s.rig_id = "rigA";
  s.num_joints = 25;
  s.joint_name.assign(25, "Joint");
  s.position.assign(25, {1.f, 2.f, 3.f});
  s.confidence.assign(25, 1.f);
  auto sb = encode(s);
  CHECK(wire::skeleton_ok(sb.data(), sb.size()));
  check_rejects_truncation(sb, wire::skeleton_ok);
  auto huge = sb;
  put_i32(huge, 16 + 4 + 5 + 8 + 4, 1 << 28);  // num_joints
  CHECK_FALSE(wire::skeleton_ok(huge.data(), huge.size()));

  std::mt19937 rng(7);
  for (int i = 0; i < 20000; ++i) {
    std::vector<uint8_t> b(rng() % 300);
    for (auto& x : b) x = static_cast<uint8_t>(rng());
    if (wire::skeleton_ok(b.data(), b.size())) {
      hullpose_msg::skeleton_t d;
      d.decode(b.data(), 0, static_cast<int>(b.size()));  // must not throw or blow up
    }
  }
}
