// CameraNode in-process (LCM memq://, nothing leaves the process): lifecycle, ROI, stamps,
// counters and configuration errors. Messages over real UDP are in test_camera_node_lcm.cpp.
#include <catch2/catch.hpp>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/camera_node/camera_node.hpp"
#include "hullpose/common/check.hpp"
#include "mask_score.hpp"
#include "test_dataset.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;
namespace fs = std::filesystem;

namespace {
// The bus of this test process (memq://: nobody listens, nothing leaves the process).
bus::Bus& memq() {
  static const std::unique_ptr<bus::Bus> bus = bus::open_bus("memq://");
  return *bus;
}

const fs::path& dataset() {
  static const test::ScratchDataset d("hullpose_test_camera_node",
                                      test::small_synth({320, 240}, 6, 20, 2), 1);
  return d.dir.path;
}

std::string error_of(const std::string& extra_or_method, bool is_method = false) {
  try {
    CameraNode node(load_node_config(test::write_node_config(
                        dataset(), 1, is_method ? extra_or_method : "horprasert", "memq://",
                        is_method ? "" : extra_or_method)),
                    memq());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("the node turns replayed frames into silhouettes close to the ground truth") {
  CameraNode node(load_node_config(test::write_node_config(dataset(), 1, "codebook", "memq://")),
                  memq());
  node.start();
  Frame frame;
  test::Score score;
  for (int f = 0; f < 6; ++f) {
    REQUIRE(node.capture(frame, 100) == GrabStatus::kFrame);
    CHECK(frame.sequence == f);
    const cv::Mat& mask = node.process(frame, TriggerStamp{100 + f, frame.capture_utime});
    score.add(mask, cv::imread(test::indexed(dataset() / "cam1", "mask", f), cv::IMREAD_GRAYSCALE));
  }
  CHECK(node.capture(frame, 100) == GrabStatus::kEndOfStream);
  CHECK(node.frames_processed() == 6);
  INFO("precision " << score.precision() << " recall " << score.recall());
  CHECK(score.f1() > 0.9);
  node.stop();
  node.stop();
}

TEST_CASE("pixels outside the ROI are background") {
  // An ROI that cuts the person of frame 1 in half.
  const cv::Mat truth =
      cv::imread(test::indexed(dataset() / "cam1", "mask", 1), cv::IMREAD_GRAYSCALE);
  const cv::Rect person = cv::boundingRect(truth);
  REQUIRE(person.area() > 100);
  const int cut = person.x + person.width / 2;
  CameraNode node(load_node_config(
                      test::write_node_config(dataset(), 1, "horprasert", "memq://",
                                              "  roi: [0, 0, " + std::to_string(cut) + ", 240]\n")),
                  memq());
  node.start();
  Frame frame;
  REQUIRE(node.capture(frame, 100) == GrabStatus::kFrame);
  REQUIRE(node.capture(frame, 100) == GrabStatus::kFrame);
  const cv::Mat& mask = node.process(frame, {});
  CHECK(cv::countNonZero(mask(cv::Rect(0, 0, cut, 240))) >
        cv::countNonZero(truth(cv::Rect(0, 0, cut, 240))) / 2);
  CHECK(cv::countNonZero(mask(cv::Rect(cut, 0, 320 - cut, 240))) == 0);
}

namespace {
// A trigger layer that stamps frames 2 and 7 as having no trigger and numbers the others + 1000;
// its trigger instants (for a simulated sensor) are 1000 + 2k.
struct ScriptedTrigger final : FrameTrigger {
  std::vector<int64_t>* seen;
  int64_t instants = 0;
  explicit ScriptedTrigger(std::vector<int64_t>* s) : seen(s) {}
  void start() override {}
  std::optional<TriggerStamp> stamp(const Frame& f) override {
    seen->push_back(f.sequence);
    if (f.sequence == 2) return std::nullopt;
    return TriggerStamp{f.sequence + 1000, f.capture_utime};
  }
  std::optional<TriggerStamp> next_instant(int) override {
    const int64_t k = instants++;
    seen->push_back(k);
    return TriggerStamp{2 * k, 1'700'000'000'000'000 + k, 0, 1'700'000'000'000'000 + k + 200};
  }
  // Free-running: every other frame is chosen, one frame late (the next frame shows it was the
  // nearest); at frame 5 also a frame that was never held.
  void offer(const Frame& f, std::vector<std::pair<int64_t, TriggerStamp>>& decided) override {
    seen->push_back(f.sequence);
    decided.clear();
    if (f.sequence % 2 == 1)
      decided.emplace_back(f.sequence - 1, TriggerStamp{2000 + f.sequence - 1, f.capture_utime});
    if (f.sequence == 5) decided.emplace_back(-7, TriggerStamp{2007, f.capture_utime});
  }
  void report(std::vector<std::pair<std::string, int64_t>>&) const override {}
};

// A camera that exposes by itself (not triggerable): the file source behind another name.
struct SelfExposing final : FrameSource {
  std::unique_ptr<FrameSource> inner;
  void start() override { inner->start(); }
  GrabStatus grab(Frame& f, int t) override { return inner->grab(f, t); }
  void stop() override { inner->stop(); }
  std::string describe() const override { return "self-exposing " + inner->describe(); }
};

SourceRegistry self_exposing_sources() {
  SourceRegistry sources = SourceRegistry::builtin();
  sources.add("file", [](const Params& p, const SourceContext& c) {
    auto s = std::make_unique<SelfExposing>();
    s->inner = SourceRegistry::builtin().create("file", p, c);
    return s;
  });
  return sources;
}
}  // namespace

TEST_CASE(
    "run() stamps a self-exposing camera's frames through the trigger and counts frames without "
    "one") {
  const SourceRegistry sources = self_exposing_sources();
  std::vector<int64_t> seen;
  CameraNode node(load_node_config(test::write_node_config(dataset(), 1, "sobs", "memq://")),
                  memq(), sources, std::make_unique<ScriptedTrigger>(&seen));
  node.start();
  const std::atomic<bool> stop{false};
  node.run(stop);
  CHECK(seen == std::vector<int64_t>{0, 1, 2, 3, 4, 5});
  CHECK(node.frames_processed() == 5);
  CHECK(node.counters().get("no_trigger") == 1);
}

TEST_CASE("run() has a simulated sensor expose the frame of each trigger instant") {
  std::vector<int64_t> seen;
  CameraNode node(load_node_config(test::write_node_config(dataset(), 1, "sobs", "memq://")),
                  memq(), SourceRegistry::builtin(), std::make_unique<ScriptedTrigger>(&seen));
  node.start();
  const std::atomic<bool> stop{false};
  node.run(
      stop);  // trigger instants 0, 2, 4 show recorded frames 0, 2, 4; instant 6 is past the end
  CHECK(seen == std::vector<int64_t>{0, 1, 2, 3});
  CHECK(node.frames_processed() == 3);
  CHECK(node.counters().get("no_trigger") == 0);
}

TEST_CASE("node configuration errors name the file and the field") {
  CHECK_THAT(error_of("vibe", true),
             Catch::Contains("camera.yaml: bgs.method: unknown method 'vibe'"));
  CHECK_THAT(error_of("  roi: [300, 0, 100, 100]\n"),
             Catch::Contains("camera.yaml: post.roi") &&
                 Catch::Contains("outside the 320x240 image of camera 1"));
  // camera 5 is not in the rig
  const fs::path cfg = test::write_node_config(dataset(), 5, "sobs", "memq://");
  CHECK_THROWS_WITH(CameraNode(load_node_config(cfg), memq()),
                    Catch::Contains("camera_id: camera 5 is not in the rig file"));
  const fs::path bad_url = test::write_node_config(dataset(), 1, "sobs", "nosuch://x");
  CHECK_THROWS_WITH(open_node_bus(load_node_config(bad_url)),
                    Catch::Contains("lcm.url: LCM 'nosuch://x' cannot be opened"));
}

TEST_CASE(
    "run() publishes a free-running camera's frames that the trigger layer chose, from the kept "
    "copies") {
  const SourceRegistry sources = self_exposing_sources();
  NodeConfig config = load_node_config(test::write_node_config(dataset(), 1, "sobs", "memq://"));
  config.trigger.free_running = true;
  std::vector<int64_t> seen;
  CameraNode node(std::move(config), memq(), sources, std::make_unique<ScriptedTrigger>(&seen));
  node.start();
  const std::atomic<bool> stop{false};
  node.run(stop);
  CHECK(seen == std::vector<int64_t>{0, 1, 2, 3, 4, 5});
  CHECK(node.frames_processed() == 3);  // frames 0, 2 and 4
  CHECK(node.counters().get("nearest_frame_gone") == 1);
  CHECK(node.counters().get("no_trigger") == 0);
}
