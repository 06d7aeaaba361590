// The hullpose-camera-node process end to end: with the synthetic source it renders its camera of
// the synthetic rig live and publishes over real LCM UDP multicast (loopback, ttl=0, a port of its
// own); this test subscribes, decodes the silhouettes and compares them with the masks the same
// node computes in-process, and with the renderer's exact silhouettes. Bad configs and absent
// cameras must end the process with a clear error, not a crash.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <sstream>

#include "hullpose/camera_node/camera_node.hpp"
#include "hullpose/camera_node/synthetic_source.hpp"
#include "hullpose/common/silhouette_codec.hpp"
#include "hullpose/synth/rig_gen.hpp"
#include "hullpose_msg/node_status_t.hpp"
#include "hullpose_msg/silhouette_t.hpp"
#include "mask_score.hpp"
#include "test_dataset.hpp"

extern char** environ;

using namespace hullpose;
using namespace hullpose::camera_node;
namespace fs = std::filesystem;

namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7683?ttl=0";

struct Child {
  pid_t pid = -1;
  fs::path stderr_file;
};

Child spawn_node(const fs::path& config, const fs::path& stderr_file) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 2, stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  std::string bin = HULLPOSE_CAMERA_NODE_BIN, flag = "--config", cfg = config.string();
  char* argv[] = {bin.data(), flag.data(), cfg.data(), nullptr};
  Child c;
  c.stderr_file = stderr_file;
  REQUIRE(posix_spawn(&c.pid, bin.c_str(), &actions, nullptr, argv, environ) == 0);
  posix_spawn_file_actions_destroy(&actions);
  return c;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Runs the node to completion; returns its exit status (-signal if it died of one).
int run_to_exit(const fs::path& config, std::string& err) {
  const Child c = spawn_node(config, config.parent_path() / "stderr.txt");
  int status = 0;
  REQUIRE(waitpid(c.pid, &status, 0) == c.pid);
  err = slurp(c.stderr_file);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

struct Received {
  std::map<int64_t, hullpose_msg::silhouette_t> silhouettes;  // by trigger_seq
  std::vector<hullpose_msg::node_status_t> statuses;
  void on_silhouette(const lcm::ReceiveBuffer*, const std::string&,
                     const hullpose_msg::silhouette_t* m) {
    silhouettes[m->trigger_seq] = *m;
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&,
                 const hullpose_msg::node_status_t* m) {
    if (m->role == "camera_node") statuses.push_back(*m);
  }
};

}  // namespace

TEST_CASE("a synthetic-source camera node process publishes its silhouettes over UDP multicast") {
  const test::ScratchDir scratch("hullpose_test_camera_node_lcm");
  const fs::path& dir = scratch.path;
  constexpr int kEmpty = 20, kFrames = 10;
  fs::remove_all(dir);
  fs::create_directories(dir);
  synth::RingRigSpec spec;
  spec.width = 320;
  spec.height = 240;
  save_rig(synth::make_ring_rig(spec), dir / "rig.yaml");
  const fs::path config = dir / "camera.yaml";
  std::ofstream(config) << "%YAML:1.0\ncamera_id: 4\nrig_file: rig.yaml\n"
                        << "lcm:\n  url: \"" << kUrl
                        << "\"\n  queue_depth: 64\n  status_period_ms: 50\n"
                        << "source:\n  type: synthetic\n  motion: walk\n  seed: 2\n  empty_frames: "
                        << kEmpty << "\n  frames: " << kFrames
                        << "\n  start_utime: \"1700000000000000\"\n"
                        << "bgs:\n  method: sobs\n  learn_frames: " << kEmpty << "\n";

  lcm::LCM sub(kUrl);
  REQUIRE(sub.good());
  Received got;
  sub.subscribe("SILHOUETTE", &Received::on_silhouette, &got);
  sub.subscribe("STATUS", &Received::on_status, &got);

  const Child child = spawn_node(config, dir / "stderr.txt");
  int status = 0;
  bool exited = false;
  // Receive while the node runs, then whatever is still in flight (until 1 s of silence).
  while (!exited) {
    sub.handleTimeout(50);
    exited = waitpid(child.pid, &status, WNOHANG) == child.pid;
  }
  while (sub.handleTimeout(1000) > 0) {
  }
  INFO(slurp(dir / "stderr.txt"));
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);

  // The same node in-process (memq://) computes the masks the process must have sent; its source
  // gives the exact silhouettes.
  NodeConfig local = load_node_config(config);
  local.lcm.url = "memq://";
  SyntheticSource* truth_source = nullptr;
  SourceRegistry sources = SourceRegistry::builtin();
  sources.add("synthetic", [&](const Params& p, const SourceContext& c) {
    auto s = std::make_unique<SyntheticSource>(p, c);
    truth_source = s.get();
    return s;
  });
  const auto bus = open_node_bus(local);
  CameraNode node(local, *bus, sources);
  node.start();
  Frame frame;
  REQUIRE(got.silhouettes.size() == kFrames);
  test::Score score;
  for (int f = kEmpty; f < kEmpty + kFrames; ++f) {
    REQUIRE(node.capture(frame, 100) == GrabStatus::kFrame);
    const cv::Mat& expected = node.process(frame, {frame.sequence, frame.capture_utime});
    REQUIRE(got.silhouettes.count(f));
    const hullpose_msg::silhouette_t& m = got.silhouettes[f];
    CHECK(m.camera_id == 4);
    CHECK(m.rig_id == "thesis8");
    CHECK(m.capture_utime == 1700000000000000 + (f * 1000000 + 15) / 30);
    CHECK(m.utime == m.capture_utime);  // free-running: stamped with its own capture time
    CHECK(m.width == 320);
    CHECK(m.height == 240);
    CHECK(m.encoding == hullpose_msg::silhouette_t::ENCODING_RLE_V1);
    CHECK(m.node_done_utime > 0);
    cv::Mat decoded;
    SilhouetteHeader header;
    REQUIRE(decode_silhouette(m.payload, {}, decoded, &header) == CodecError::kNone);
    CHECK(header.roi == PixelRoi{m.roi_x, m.roi_y, m.roi_width, m.roi_height});
    CHECK(cv::countNonZero(decoded != expected) == 0);
    score.add(decoded, truth_source->truth());
  }
  INFO("precision " << score.precision() << " recall " << score.recall());
  CHECK(score.f1() > 0.9);
  CHECK(node.capture(frame, 100) == GrabStatus::kEndOfStream);

  REQUIRE(!got.statuses.empty());
  const hullpose_msg::node_status_t& last = got.statuses.back();
  CHECK(last.node_id == 4);
  CHECK(last.rig_id == "thesis8");
  CHECK(last.state == hullpose_msg::node_status_t::STATE_STOPPED);
  CHECK(last.frames_total == kFrames);
  CHECK(last.last_trigger_seq == kEmpty + kFrames - 1);
  CHECK(last.num_stages == 4);
  std::map<std::string, int64_t> counters;
  for (int i = 0; i < last.num_counters; ++i)
    counters[last.counter_name[static_cast<size_t>(i)]] =
        last.counter_value[static_cast<size_t>(i)];
  CHECK(counters["messages_sent"] == kFrames);
  CHECK(counters["bytes_sent"] > 0);
  CHECK(counters.at("queue_full") == 0);
  CHECK(counters.at("publish_error") == 0);
}

TEST_CASE("the camera node process fails cleanly on a malformed config or an absent camera") {
  const test::ScratchDir scratch("hullpose_test_camera_node_errors");
  const fs::path& dir = scratch.path;
  test::write_dataset(dir, test::small_synth({64, 48}, 1, 1, 1), 0);
  std::string err;

  std::ofstream(dir / "malformed.yaml") << "%YAML:1.0\ncamera_id: 0\nrig_file: rig.yaml\nsource: "
                                           "{type: file}\nbgs: {learn_frames: 3}\n";
  CHECK(run_to_exit(dir / "malformed.yaml", err) == 2);
  CHECK_THAT(err, Catch::Contains("hullpose-camera-node: error:") &&
                      Catch::Contains("malformed.yaml:5: bgs.method: missing"));

  std::ofstream(dir / "garbage.yaml") << "camera_id: [1, 2\n\t: : :\n";
  CHECK(run_to_exit(dir / "garbage.yaml", err) == 2);
  CHECK_THAT(err, Catch::Contains("garbage.yaml"));

  const fs::path v4l2 = test::write_node_config(dir, 0, "horprasert", kUrl);
  std::string text = slurp(v4l2);
  const auto replace_source = [&](const std::string& source) {
    std::string t = text;
    const size_t a = t.find("source:"), b = t.find("bgs:");
    t.replace(a, b - a, source);
    t.replace(t.find("  background:"),
              t.find('\n', t.find("  background:")) - t.find("  background:") + 1, "");
    return t;
  };
  std::ofstream(dir / "v4l2.yaml")
      << replace_source("source:\n  type: v4l2\n  device: /dev/video-hullpose-absent\n");
  CHECK(run_to_exit(dir / "v4l2.yaml", err) == 2);
  CHECK_THAT(err, Catch::Contains("v4l2 device /dev/video-hullpose-absent: cannot open"));

  std::ofstream(dir / "libcamera.yaml")
      << replace_source("source:\n  type: libcamera\n  camera: imx296-absent\n");
  CHECK(run_to_exit(dir / "libcamera.yaml", err) == 2);
  CHECK_THAT(err, Catch::Contains("libcamera: camera 'imx296-absent' not found"));

  // The trigger input is opened at start: a board without the GPIO chip says which chip and line.
  std::ofstream(dir / "gpiod.yaml")
      << text << "trigger:\n  edges: gpiod\n  chip: gpiochip-hullpose-absent\n  line: 17\n";
  CHECK(run_to_exit(dir / "gpiod.yaml", err) == 2);
  CHECK_THAT(
      err,
      Catch::Contains(
          "hullpose-camera-node: error: camera 0: trigger input gpiod:gpiochip-hullpose-absent:17: "
          "cannot open GPIO chip 'gpiochip-hullpose-absent' line 17"));
}
