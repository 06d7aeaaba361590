// Fuzz target: the LCM wire checks and decoders of every message type (hullpose/msg/wire.hpp,
// then lcm-gen's decode; the first byte picks the type). A message the check passes decodes to
// exactly its size and re-encodes stably; a hull_t that decodes then goes through the view's
// field-by-field check (msg::from_message), which must never throw or read out of bounds.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <hullpose_msg/hull_t.hpp>
#include <hullpose_msg/node_status_t.hpp>
#include <hullpose_msg/silhouette_t.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <vector>

#include "../rig/rig_fixtures.hpp"
#include "hullpose/msg/hull.hpp"
#include "hullpose/msg/wire.hpp"

namespace {
template <typename Msg>
bool ok(const uint8_t* data, size_t size) {
  return hullpose::wire::well_formed({data, size}, static_cast<const Msg*>(nullptr));
}
template <typename Msg>
const Msg* check(const uint8_t* data, size_t size) {
  if (!ok<Msg>(data, size)) return nullptr;
  static Msg m;
  static std::vector<uint8_t> once, twice;
  const int used = m.decode(data, 0, static_cast<int>(size));
  if (used < 0) return nullptr;  // the check leaves the type fingerprint to the decoder
  if (used != static_cast<int>(size)) std::abort();
  // Re-encoding normalises (booleans to 0/1; a string cut at an embedded NUL, as lcm-gen encodes
  // with strlen): it must pass the check itself and be stable.
  once.resize(static_cast<size_t>(m.getEncodedSize()));
  const int n = m.encode(once.data(), 0, static_cast<int>(once.size()));
  if (n <= 0) std::abort();
  once.resize(static_cast<size_t>(n));  // getEncodedSize counts a string's bytes after a NUL too
  if (!ok<Msg>(once.data(), once.size()) ||
      !hullpose::wire::decode(std::span<const uint8_t>(once), m))
    std::abort();
  twice.resize(once.size());
  m.encode(twice.data(), 0, n);
  if (std::memcmp(once.data(), twice.data(), once.size()) != 0) std::abort();
  return &m;
}
template <typename Msg>
std::vector<uint8_t> encoded(const Msg& m, uint8_t type) {
  std::vector<uint8_t> b(1 + static_cast<size_t>(m.getEncodedSize()));
  b[0] = type;
  m.encode(b.data() + 1, 0, static_cast<int>(b.size() - 1));
  return b;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  switch (data[0] % 5) {
    case 0:
      check<hullpose_msg::silhouette_t>(data + 1, size - 1);
      break;
    case 1:
      check<hullpose_msg::trigger_t>(data + 1, size - 1);
      break;
    case 2:
      check<hullpose_msg::skeleton_t>(data + 1, size - 1);
      break;
    case 3:
      check<hullpose_msg::node_status_t>(data + 1, size - 1);
      break;
    default:
      if (const auto* h = check<hullpose_msg::hull_t>(data + 1, size - 1)) {
        static hullpose::msg::CoarseHull out;
        if (hullpose::msg::from_message(*h, out) == hullpose::msg::HullError::kNone &&
            (out.occupancy.cols != h->nx || out.occupancy.rows != h->ny * h->nz))
          std::abort();
      }
      break;
  }
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  const hullpose::Rig rig = hullpose::testing::make_rig(2);
  hullpose_msg::trigger_t t{};
  t.utime = 1'700'000'000'000'000;
  t.rig_id = "rigA";
  t.seq = 42;
  t.period_us = 33'333;
  hullpose_msg::skeleton_t s{};
  s.rig_id = "rigA";
  s.num_joints = 3;
  s.joint_name = {"HeadTop", "Head", "Neck"};
  s.position.assign(3, {1.f, 2.f, 3.f});
  s.confidence.assign(3, 0.5f);
  hullpose_msg::node_status_t st{};
  st.rig_id = "rigA";
  st.role = "camera_node";
  st.hostname = "cam1";
  st.message = "running";
  st.num_stages = 1;
  st.stage_name = {"capture"};
  st.stage_ms = {1.5f};
  st.num_counters = 2;
  st.counter_name = {"late", "auth_replayed"};
  st.counter_value = {3, 0};
  hullpose::msg::CoarseHull h;
  h.dims = {4, 3, 2};
  h.origin_mm = {-100, -100, 0};
  h.voxel_mm = 100;
  h.carved_voxel_mm = 25;
  h.occupancy = cv::Mat::zeros(6, 4, CV_8UC1);
  h.occupancy.at<uint8_t>(4, 2) = 255;
  h.occupancy.at<uint8_t>(5, 3) = 255;
  h.num_occupied = 2;
  hullpose::SilhouetteEncoder enc;
  hullpose_msg::hull_t hm;
  hullpose::msg::to_message(h, "rigA", enc, hm);
  return {encoded(hullpose::testing::make_silhouette(rig, 1, 7, t.utime), 0), encoded(t, 1),
          encoded(s, 2), encoded(st, 3), encoded(hm, 4)};
}
