#include <catch2/catch.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <random>

#include "hullpose/msg/reasons.hpp"
#include "hullpose/msg/wire.hpp"
#include "rig_fixtures.hpp"

using namespace hullpose;
using hullpose::testing::encode;

namespace {
void put_i32(std::vector<uint8_t>& b, size_t at, int32_t v) {
  for (int k = 0; k < 4; ++k)
    b[at + static_cast<size_t>(k)] = static_cast<uint8_t>(static_cast<uint32_t>(v) >> (24 - 8 * k));
}
template <class Msg>
bool ok(const std::vector<uint8_t>& b, size_t n) {
  Msg m;
  return wire::decode(std::span<const uint8_t>(b.data(), n), m);
}
template <class Msg>
bool ok(const std::vector<uint8_t>& b) {
  return ok<Msg>(b, b.size());
}
template <class Msg>
void check_rejects_truncation(const std::vector<uint8_t>& b) {
  for (size_t n = 0; n < b.size(); ++n) CHECK_FALSE(ok<Msg>(b, n));
  auto longer = b;
  longer.push_back(0);
  CHECK_FALSE(ok<Msg>(longer));
}
}  // namespace

TEST_CASE("wire checks accept encoded messages and reject truncations and hostile lengths") {
  const Rig rig = testing::make_rig(1);
  auto sil = encode(testing::make_silhouette(rig, 0, 4, 1000));
  using hullpose_msg::silhouette_t, hullpose_msg::trigger_t, hullpose_msg::skeleton_t,
      hullpose_msg::node_status_t;
  CHECK(ok<silhouette_t>(sil));
  check_rejects_truncation<silhouette_t>(sil);
  for (int32_t v : {0, -1, 1 << 30}) {
    auto b = sil;
    put_i32(b, 16, v);  // rig_id length
    CHECK_FALSE(ok<silhouette_t>(b));
  }
  const size_t payload_at = 16 + 4 + 5 + 4 + 8 + 8 + 24 + 1;
  for (int32_t v : {-1, -100, 0x7fffffff, 5}) {
    auto b = sil;
    put_i32(b, payload_at, v);
    CHECK_FALSE(ok<silhouette_t>(b));
  }

  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  auto tb = encode(t);
  CHECK(ok<trigger_t>(tb));
  check_rejects_truncation<trigger_t>(tb);

  hullpose_msg::skeleton_t s{};
  s.rig_id = "rigA";
  s.num_joints = 25;
  s.joint_name.assign(25, "Joint");
  s.position.assign(25, {1.f, 2.f, 3.f});
  s.confidence.assign(25, 1.f);
  auto sb = encode(s);
  CHECK(ok<skeleton_t>(sb));
  check_rejects_truncation<skeleton_t>(sb);
  auto huge = sb;
  put_i32(huge, 16 + 4 + 5 + 8 + 4, 1 << 28);  // num_joints
  CHECK_FALSE(ok<skeleton_t>(huge));

  hullpose_msg::node_status_t st{};
  st.rig_id = "rigA";
  st.role = "fusion_host";
  st.hostname = "h";
  st.message = "m";
  st.stage_name = {"a", "b"};
  st.stage_ms = {1.f, 2.f};
  st.num_stages = 2;
  st.counter_name = {"c"};
  st.counter_value = {3};
  st.num_counters = 1;
  auto stb = encode(st);
  CHECK(ok<node_status_t>(stb));
  check_rejects_truncation<node_status_t>(stb);

  std::mt19937 rng(7);
  for (int i = 0; i < 20000; ++i) {
    std::vector<uint8_t> b(rng() % 300);
    for (auto& x : b) x = static_cast<uint8_t>(rng());
    hullpose_msg::skeleton_t d;
    wire::decode(std::span<const uint8_t>(b), d);  // must not throw or blow up
    hullpose_msg::node_status_t n;
    wire::decode(std::span<const uint8_t>(b), n);
  }
}

TEST_CASE("the reason table names every REASON_* of skeleton_t.lcm, and unknown codes by number") {
  CHECK(msg::reason_name(hullpose_msg::skeleton_t::REASON_OK) == "ok");
  CHECK(msg::reason_name(hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS) == "too_few_cameras");
  CHECK(msg::reason_name(hullpose_msg::skeleton_t::REASON_FIT_FAILED) == "fit_failed");
  CHECK(msg::reason_name(42) == "reason_42");
  CHECK(msg::reason_name(-1) == "reason_-1");
}
