// The live service over LCM's in-process provider (memq://) and a test clock: assembly, the
// pipeline seam, SKELETON with its latency breakdown and reasons, STATUS with the drop counters.
// Deadlines pass because the test moves the clock, never because real time went by.
#include <catch2/catch.hpp>
#include <hullpose_msg/node_status_t.hpp>
#include <map>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/clock.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"
#include "hullpose/msg/wire.hpp"
#include "rig_fixtures.hpp"
#include "seq_check_pipeline.hpp"

using namespace hullpose;

namespace {
struct Sink {
  std::map<int64_t, hullpose_msg::skeleton_t> skeletons;
  std::vector<hullpose_msg::node_status_t> status;
  void on_skeleton(std::span<const uint8_t> bytes) {
    hullpose_msg::skeleton_t s;
    REQUIRE(wire::decode(bytes, s));
    skeletons[s.trigger_seq] = s;
  }
  void on_status(std::span<const uint8_t> bytes) {
    hullpose_msg::node_status_t s;
    REQUIRE(wire::decode(bytes, s));
    status.push_back(s);
  }
};

hullpose_msg::silhouette_t seq_silhouette(const Rig& rig, int cam, int64_t seq, int64_t utime) {
  auto m = testing::make_silhouette(rig, cam, seq, utime);
  cv::Mat mask(rig.find(cam)->height, rig.find(cam)->width, CV_8UC1);
  testing::draw_seq_mask(mask, seq, cam);
  const PixelRoi roi = SilhouetteEncoder().encode(mask, m.payload);
  m.payload_size = static_cast<int32_t>(m.payload.size());
  m.roi_x = roi.x;
  m.roi_y = roi.y;
  m.roi_width = roi.width;
  m.roi_height = roi.height;
  return m;
}
}  // namespace

TEST_CASE("fusion service: every sequence is published, fused or with its reason, with latencies") {
  const Rig rig = testing::make_rig(3, 120, 90);
  const auto bus = bus::open_bus("memq://");
  SimClock clock;
  testing::SeqCheckPipeline pipeline;
  fusion::ServiceConfig cfg;
  cfg.assembler.min_cameras = 2;
  cfg.assembler.deadline_us = 5'000;
  cfg.assembler.no_views_timeout_us = 5'000;
  fusion::FusionService service(*bus, clock, rig, pipeline, cfg);
  Sink sink;
  const auto skeletons = bus->subscribe(
      "SKELETON", [&](std::span<const uint8_t> b, const std::string&) { sink.on_skeleton(b); },
      100);
  const auto status = bus->subscribe(
      "STATUS", [&](std::span<const uint8_t> b, const std::string&) { sink.on_status(b); }, 100);

  const int64_t period = 33'333;
  const int64_t t0 = clock.realtime_utime() - 10 * period;
  hullpose_msg::trigger_t trig{};
  trig.rig_id = rig.rig_id;
  trig.period_us = static_cast<int32_t>(period);
  trig.epoch = 5;
  for (int64_t seq = 0; seq < 8; ++seq) {
    trig.seq = seq;
    trig.utime = t0 + seq * period;
    wire::publish(*bus, "TRIGGER", trig);
    const int cams = seq < 5 ? 3 : seq == 5 ? 2 : seq == 6 ? 1 : 0;  // seq 7: announced, no views
    for (int cam = 0; cam < cams; ++cam) {
      auto m = seq_silhouette(rig, cam, seq, trig.utime);
      wire::publish(*bus, "SILHOUETTE", m);
    }
  }
  const uint8_t garbage[] = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  bus->publish("SILHOUETTE", garbage);
  bus->publish("TRIGGER", garbage);
  // Every message is handled at once (memq delivers synchronously to the queue); then the clock
  // moves past the 5 ms deadline of every frame, 1 ms per step.
  for (int i = 0; i < 50 && sink.skeletons.size() < 8; ++i) {
    service.step(0);
    clock.advance(1'000);
  }
  service.flush();
  while (bus->handle(0)) {
  }

  REQUIRE(sink.skeletons.size() == 8);
  for (int64_t seq = 0; seq < 8; ++seq) {
    const auto& s = sink.skeletons.at(seq);
    INFO("seq " << seq);
    CHECK(s.rig_id == rig.rig_id);
    CHECK(s.utime == t0 + seq * period);
    CHECK(s.num_joints == 25);
    CHECK(s.joint_name[0] == "HeadTop");
    CHECK(s.joint_name[24] == "RToe");
    if (seq <= 5) {
      CHECK(s.valid);
      CHECK(s.reason == hullpose_msg::skeleton_t::REASON_OK);
      CHECK(s.position[0][0] == static_cast<float>(seq));
      CHECK(s.num_cameras_used == (seq < 5 ? 3 : 2));
      CHECK(s.cameras_used_mask == (seq < 5 ? 0b111 : 0b011));
      CHECK(s.capture_us == 300);
      CHECK(s.node_done_us == 5000);
      CHECK(s.received_us >= s.node_done_us);
      CHECK(s.fused_us >= s.received_us);
      CHECK(s.published_us >= s.fused_us);
    } else {
      CHECK_FALSE(s.valid);
      CHECK(s.reason == hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS);
      CHECK(s.num_cameras_used == (seq == 6 ? 1 : 0));
    }
  }
  CHECK(pipeline.frames == 6);
  CHECK(service.assembler().counters().get("malformed_lcm") == 1);
  CHECK(service.counters().get("malformed_trigger") == 1);
  REQUIRE_FALSE(sink.status.empty());
  const auto& st = sink.status.back();
  CHECK(st.role == "fusion_host");
  CHECK(st.state == hullpose_msg::node_status_t::STATE_DEGRADED);
  CHECK(st.frames_total == 8);
  std::map<std::string, int64_t> counters;
  for (int i = 0; i < st.num_counters; ++i)
    counters[st.counter_name[static_cast<size_t>(i)]] = st.counter_value[static_cast<size_t>(i)];
  CHECK(counters["fused_complete"] == 5);
  CHECK(counters["fused_partial"] == 1);
  CHECK(counters["too_few_cameras"] == 1);
  CHECK(counters["no_views"] == 1);
  CHECK(counters["malformed_lcm"] == 1);
}

TEST_CASE("fusion service: a pipeline that throws fails that frame only; the service goes on") {
  const Rig rig = testing::make_rig(2, 60, 40);
  const auto bus = bus::open_bus("memq://");
  SimClock clock;
  struct Throwing final : fusion::FramePipeline {
    void process(const fusion::AssembledFrame& f, fusion::PoseEstimate& out) override {
      if (f.trigger_seq == 1)
        throw std::runtime_error("CUDA backend: cudaMemcpy: an illegal memory access");
      out.valid = true;
    }
  } pipeline;
  fusion::ServiceConfig cfg;
  cfg.assembler.min_cameras = 2;
  fusion::FusionService service(*bus, clock, rig, pipeline, cfg);
  Sink sink;
  const auto skeletons = bus->subscribe(
      "SKELETON", [&](std::span<const uint8_t> b, const std::string&) { sink.on_skeleton(b); },
      100);
  const int64_t t0 = clock.realtime_utime();
  for (int64_t seq = 0; seq < 3; ++seq)
    for (int cam = 0; cam < 2; ++cam)
      wire::publish(*bus, "SILHOUETTE", testing::make_silhouette(rig, cam, seq, t0 + seq * 33'333));
  for (int i = 0; i < 20; ++i) service.step(0);
  service.flush();
  while (bus->handle(0)) {
  }
  REQUIRE(sink.skeletons.size() == 3);
  CHECK(sink.skeletons.at(0).valid);
  CHECK_FALSE(sink.skeletons.at(1).valid);
  CHECK(sink.skeletons.at(1).reason == hullpose_msg::skeleton_t::REASON_FIT_FAILED);
  CHECK(sink.skeletons.at(2).valid);
  CHECK(service.counters().get("pipeline_error") == 1);
}

TEST_CASE("views laid out by camera index for carving") {
  const Rig rig = testing::make_rig(4, 40, 30);
  std::vector<cv::Mat> masks;
  std::vector<PixelRoi> rois;
  int calls = 0;
  fusion::FrameAssembler fa(rig, {}, [&](const fusion::AssembledFrame& f) {
    ++calls;
    fusion::views_by_camera_index(f, rig.cameras.size(), masks, rois);
    REQUIRE(masks.size() == 4);
    CHECK(masks[1].empty());
    CHECK(rois[1] == PixelRoi{});
    for (size_t i : {size_t{0}, size_t{2}, size_t{3}}) {
      CHECK(masks[i].size() == cv::Size(40, 30));
      CHECK(masks[i].data == f.views[i == 0 ? 0 : i - 1].mask->data);  // shared, not copied
      CHECK(rois[i].width > 0);
    }
  });
  const int64_t u = realtime_utime();
  for (int cam : {0, 2, 3}) {
    auto m = testing::make_silhouette(rig, cam, 1, u);
    fa.on_silhouette(m, u, 0);
  }
  fa.flush();
  CHECK(calls == 1);
}

TEST_CASE("service command line: --help exits 0 before anything opens; bad options exit 2") {
  const auto run = [](const std::vector<const char*>& options) {
    std::vector<const char*> args{"fusion-host-test"};
    args.reserve(options.size() + 1);
    for (const char* o : options) args.push_back(o);
    bool built = false;
    const int rc =
        run_tool("fusion-host-test", static_cast<int>(args.size()), args.data(),
                 [&built](int c, const char* const* v) {
                   return fusion::service_main(c, v, "fusion-host-test",
                                               [&built](const Rig&, const fusion::PipelineOptions&)
                                                   -> std::unique_ptr<fusion::FramePipeline> {
                                                 built = true;
                                                 return nullptr;
                                               });
                 });
    CHECK_FALSE(built);
    return rc;
  };
  CHECK(run({"--help"}) == 0);
  CHECK(run({"--rig", "x.yaml", "--frobnicate"}) == 2);
  CHECK(run({"--rig", "x.yaml", "--max-open", "0"}) == 2);
  CHECK(run({"--rig", "x.yaml", "--deadline-ms", "soon"}) == 2);
  CHECK(run({"--deadline-from", "never", "--rig", "x.yaml"}) == 2);
  CHECK(run({"--rig", "x.yaml", "--lag-frames", "2"}) == 2);
  CHECK(run({"--resolution", "128"}) == 2);  // no --rig
}

TEST_CASE("fusion service: each SKELETON waits for the next frame and is smoothed with it") {
  const Rig rig = testing::make_rig(2, 60, 40);
  const auto bus = bus::open_bus("memq://");
  SimClock clock;
  // Every joint of frame n at x = 10 n + 4 (-1)^n: a steady walk with a frame-to-frame error that
  // the centred mean of frames n - 1, n, n + 1 (weights 1/4, 1/2, 1/4) takes out.
  struct Zigzag final : fusion::FramePipeline {
    void process(const fusion::AssembledFrame& f, fusion::PoseEstimate& out) override {
      const auto x = static_cast<float>(10 * f.trigger_seq + (f.trigger_seq % 2 == 0 ? 4 : -4));
      for (auto& p : out.position_mm) p = {x, 0.f, 0.f};
      out.valid = true;
    }
  } pipeline;
  const int64_t release_us = fusion::ServiceConfig{}.lag_release_us;
  // What was published after frames 0-2 were fused, after a pause of lag_release_us, and after
  // frames 3-4 came.
  using Published = std::map<int64_t, hullpose_msg::skeleton_t>;
  const auto run = [&](int lag_frames) {
    fusion::ServiceConfig cfg;
    cfg.assembler.min_cameras = 2;
    cfg.assembler.deadline_us = 5'000;
    cfg.lag.frames = lag_frames;
    fusion::FusionService service(*bus, clock, rig, pipeline, cfg);
    Sink sink;
    const auto skeletons = bus->subscribe(
        "SKELETON", [&](std::span<const uint8_t> b, const std::string&) { sink.on_skeleton(b); },
        100);
    const int64_t t0 = clock.realtime_utime() - 100'000;  // triggered before they arrive
    const auto frames = [&](int64_t first, int64_t end) {
      for (int64_t seq = first; seq < end; ++seq)
        for (int cam = 0; cam < 2; ++cam)
          wire::publish(*bus, "SILHOUETTE",
                        testing::make_silhouette(rig, cam, seq, t0 + seq * 33'333));
      for (int i = 0; i < 20; ++i) {  // 20 ms: every frame fused, none held past lag_release_us
        service.step(0);
        clock.advance(1'000);
      }
      while (bus->handle(0)) {
      }
      return sink.skeletons;
    };
    const Published fused = frames(0, 3);
    clock.advance(cfg.lag_release_us);
    service.step(0);
    while (bus->handle(0)) {
    }
    const Published released = sink.skeletons;
    return std::tuple{fused, released, frames(3, 5)};
  };

  SECTION("--lag-frames 1 (default): one frame late, smoothed; released as fitted after a pause") {
    const auto [fused, released, resumed] = run(1);
    REQUIRE(fused.size() == 2);              // frame 2 waits for a frame 3
    CHECK(fused.at(0).position[0][0] == 4);  // no frame before it
    CHECK(fused.at(1).position[0][0] == 10);
    CHECK(fused.at(1).position[24][0] == 10);
    REQUIRE(released.size() == 3);  // none came within lag_release_us
    CHECK(released.at(2).position[0][0] == 24);
    CHECK(released.at(2).published_us >= release_us);  // its 33 ms since the trigger + the wait
    CHECK(released.at(2).utime == fused.at(0).utime + 2 * 33'333);
    // Frame 3 waits for frame 4 and is smoothed with it and with the released frame 2.
    REQUIRE(resumed.size() == 4);
    CHECK(resumed.at(3).position[0][0] == 30);
  }
  SECTION("--lag-frames 0: each frame as soon as it is fused, as fitted") {
    const auto [fused, released, resumed] = run(0);
    REQUIRE(fused.size() == 3);
    CHECK(fused.at(0).position[0][0] == 4);
    CHECK(fused.at(1).position[0][0] == 6);
    CHECK(fused.at(2).position[0][0] == 24);
    CHECK(fused.at(2).published_us < release_us);
    REQUIRE(resumed.size() == 5);
    CHECK(resumed.at(3).position[0][0] == 26);
  }
}
