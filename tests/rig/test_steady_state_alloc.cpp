// "No allocations in per-frame loops at steady state", measured: global operator new is
// counted while the trigger listener and the frame assembler run frame after frame.
#include <catch2/catch.hpp>

#include "hullpose/camera_node/trigger_listener.hpp"
#include "hullpose/fusion_host/frame_assembler.hpp"
#include "rig_fixtures.hpp"
#include "support/alloc_count.hpp"

using namespace hullpose;

TEST_CASE("trigger listener: no allocation per frame at steady state") {
  trigger::SimEdgeSource edges;
  trigger::ListenerConfig cfg;
  cfg.rig_id = "rigA";
  trigger::TriggerListener listener(cfg, edges);
  std::vector<trigger::TaggedFrame> out;
  out.reserve(64);
  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  t.period_us = 33'333;
  t.epoch = 4;
  const int64_t off = 2'000'000;
  long during = 0;
  int64_t tagged = 0;
  for (int k = 0; k < 400; ++k) {
    if (k == 200) during = hullpose::test::allocations();
    t.seq = k;
    t.utime = 1'700'000'000'000'000 + k * 33'333;
    if (k % 7 != 3) listener.on_announcement(t, t.utime + off + 900);  // some announcements lost
    listener.on_frame(k, t.utime + off + 200);
    out.clear();
    listener.poll(t.utime + off + 1000, out);
    tagged += static_cast<int64_t>(out.size());
    // The edge source is a std::deque in tests: push outside the measured window's accounting.
    const long before_push = hullpose::test::allocations();
    edges.push(t.utime + off + 33'333);
    during += hullpose::test::allocations() - before_push;
  }
  CHECK(hullpose::test::allocations() - during == 0);
  CHECK(tagged > 390);
}

TEST_CASE("frame assembler: no allocation per frame at steady state, hostile messages included") {
  const Rig rig = testing::make_rig(8, 320, 240);
  fusion::AssemblerConfig cfg;
  cfg.min_cameras = 5;
  int64_t closed = 0;
  fusion::FrameAssembler fa(rig, cfg, [&](const fusion::AssembledFrame& f) {
    closed += static_cast<int64_t>(f.views.size());
  });
  const int64_t t0 = 1'700'000'000'000'000, p = 33'333;
  std::vector<std::vector<uint8_t>> msgs;
  for (int64_t seq = 0; seq < 300; ++seq)
    for (int cam = 0; cam < 8; ++cam)
      msgs.push_back(testing::encode(testing::make_silhouette(rig, cam, seq, t0 + seq * p)));
  std::vector<uint8_t> garbage(100, 0xAB);
  long before = 0;
  for (size_t i = 0; i < msgs.size(); ++i) {
    if (i == msgs.size() / 2) before = hullpose::test::allocations();
    const int64_t seq = static_cast<int64_t>(i / 8);
    if (i % 8 == 5 && seq % 4 == 0) continue;  // a camera's message lost now and then
    fa.on_bytes(msgs[i], t0 + seq * p + 8000, seq * p);
    if (i % 16 == 0) fa.on_bytes(garbage, 0, seq * p);
    fa.poll(seq * p + 1000);
  }
  CHECK(hullpose::test::allocations() - before == 0);
  CHECK(closed > 2300);
}
