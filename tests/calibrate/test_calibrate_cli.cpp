// hullpose-calibrate run as a process on a folder of rendered images (issue 9): it writes a rig
// file the foundation's loader accepts and the report; a capture in which one camera never
// shares a board view fails naming that camera. The same images replayed through camera-node
// frame sources (the file backend) make a live calibration with per-image feedback, and a live
// source whose device is absent fails with a clear message. A 4-camera subset of the synthetic
// rig keeps the detection work (the run time) small; accuracy is test_calibrate_synthetic's job.
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>

#include "hullpose/calibrate/live_provider.hpp"
#include "hullpose/calibrate/rig_calibrator.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/rig.hpp"
#include "synthetic_capture.hpp"

using namespace hullpose;
using namespace hullpose::calibrate;
using namespace hullpose::calibrate::testing;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

const BoardSpec kBoard{13, 8, 80};

// Rendered once: cam<ID>/<view>.png for the folder runs and cam<ID>/live_NNN.png (a grey frame
// where the camera cannot see the board) for the file sources, plus the true rig's file.
struct RenderedCapture {
  fs::path dir = fs::path(HULLPOSE_BINARY_DIR) / "tests" / "calibrate" / "cli_capture";
  Rig truth;
  std::vector<PlannedView> plan;
  std::set<std::pair<std::string, int>> rendered;  // (view, camera) pairs with an image

  RenderedCapture() {
    const Rig ring = make_ring_rig(7);
    truth.rig_id = "synthetic-4";
    truth.volume = ring.volume;
    for (int k : {0, 2, 4, 7}) truth.cameras.push_back(ring.cameras[static_cast<size_t>(k)]);
    plan = make_capture_plan(truth, kBoard, {.close_ups = 7, .shared = 14, .floors = 3}, 21);
    fs::remove_all(dir);
    const BoardRenderer renderer(truth, kBoard, 0.3 / std::sqrt(2.0), 2.0);
    SyntheticViewProvider provider(truth, renderer, plan, 5);
    CaptureInstant instant;
    for (int index = 0; provider.next(instant); ++index) {
      for (const auto& cam : truth.cameras) {
        cv::Mat live(cam.height, cam.width, CV_8UC1, cv::Scalar(110));
        for (const auto& image : instant.images)
          if (image.camera_id == cam.id) {
            live = image.image;
            const fs::path folder = dir / "images" / ("cam" + std::to_string(cam.id));
            fs::create_directories(folder);
            REQUIRE(cv::imwrite((folder / (instant.name + ".png")).string(), image.image));
            rendered.emplace(instant.name, cam.id);
          }
        char name[32];
        std::snprintf(name, sizeof name, "live_%03d.png", index);
        const fs::path folder = dir / "live" / ("cam" + std::to_string(cam.id));
        fs::create_directories(folder);
        REQUIRE(cv::imwrite((folder / name).string(), live));
      }
    }
    save_rig(truth, dir / "nominal_rig.yaml");
  }

  // A node config for camera `id` whose source is `source` (YAML mapping body).
  fs::path node_config(int id, const std::string& source) const {
    const fs::path file = dir / ("node" + std::to_string(id) + ".yaml");
    std::ofstream out(file);
    out << "%YAML:1.0\n---\ncamera_id: " << id << "\nrig_file: nominal_rig.yaml\nsource:\n"
        << source << "bgs:\n  method: mog2\n";
    return file;
  }
};

const RenderedCapture& capture() {
  static const RenderedCapture c;
  return c;
}

struct Process {
  int status = -1;
  std::string output;
};

Process run_calibrate(const std::string& args) {
  const fs::path log = capture().dir / "calibrate.log";
  const std::string command =
      std::string(HULLPOSE_CALIBRATE_EXE) + " " + args + " > " + log.string() + " 2>&1";
  Process p;
  const int raw = std::system(command.c_str());
  p.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  p.output = text.str();
  return p;
}

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("hullpose-calibrate turns a folder of images into a rig file and a report") {
  const RenderedCapture& c = capture();
  const fs::path rig_file = c.dir / "calibrated.yaml";
  const fs::path report = c.dir / "report.txt";
  const Process p = run_calibrate("--images " + (c.dir / "images").string() +
                                  " --board 13x8 --square-mm 80 --out " + rig_file.string() +
                                  " --report " + report.string() +
                                  " --rig-id lab --floor-view floor --floor-view floor2"
                                  " --floor-view floor3");
  INFO(p.output);
  REQUIRE(p.status == 0);
  CHECK_THAT(p.output, Contains("cam0 a00_close00: board found; 1 views, coverage"));
  CHECK_THAT(p.output, Contains("wrote " + rig_file.string()));
  const Rig rig = load_rig(rig_file);  // the foundation's loader validates it
  CHECK(rig.rig_id == "lab");
  REQUIRE(rig.cameras.size() == c.truth.cameras.size());
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    const CameraModel& t = c.truth.cameras[i];
    const CameraModel& e = rig.cameras[i];
    INFO("camera " << t.id);
    CHECK(e.id == t.id);
    CHECK(e.width == t.width);
    // Four cameras and a few views each: a sane rig, not issue 9's tolerances (which
    // test_calibrate_synthetic checks on a full capture).
    CHECK(std::abs(e.fx / t.fx - 1) < 0.02);
    CHECK((e.centre() - t.centre()).norm() < 100.0);
    CHECK(angle_deg(e.R, t.R) < 2.0);
  }
  std::ifstream in(report);
  std::stringstream text;
  text << in.rdbuf();
  CHECK_THAT(text.str(), Contains("rms-intrinsic  rms-rig"));
  CHECK_THAT(text.str(), Contains("rig 'lab': 4 cameras"));
  CHECK_THAT(text.str(), Contains("3 floor boards set the world frame"));
  CHECK_THAT(text.str(), Contains("capture volume"));
}

TEST_CASE(
    "hullpose-calibrate refuses a capture in which one camera never shares a board view, naming "
    "it") {
  const RenderedCapture& c = capture();
  // Camera 4 keeps only its own close-ups; nobody else keeps those.
  const fs::path bad = c.dir / "bad";
  fs::remove_all(bad);
  for (const auto& [view, id] : c.rendered) {
    const bool cam4_closeup = view.rfind("a04_", 0) == 0;
    if (id == 4 ? !cam4_closeup : cam4_closeup) continue;
    const fs::path to = bad / ("cam" + std::to_string(id)) / (view + ".png");
    fs::create_directories(to.parent_path());
    fs::copy_file(c.dir / "images" / ("cam" + std::to_string(id)) / (view + ".png"), to);
  }
  const fs::path rig_file = c.dir / "bad.yaml";
  fs::remove(rig_file);
  // Enough views for camera 4's intrinsics on its own: linking is what fails.
  const Process p = run_calibrate("--quiet --min-views 5 --images " + bad.string() +
                                  " --board 13x8 --square-mm 80 --out " + rig_file.string());
  INFO(p.output);
  CHECK(p.status == 2);
  CHECK_THAT(p.output, Contains("error: camera 4 could not be linked to the rig"));
  CHECK(!fs::exists(rig_file));
}

TEST_CASE("live calibration from camera-node frame sources, with feedback as views arrive") {
  const RenderedCapture& c = capture();
  // Two of the cameras (the ceiling camera links to every other): half the detection work.
  const std::vector<int> ids{0, 7};
  std::vector<LiveCamera> cameras;
  for (int id : ids)
    cameras.push_back(live_camera_from_node_config(c.node_config(
        id, "  type: file\n  path: live/cam" + std::to_string(id) + "/live_%03d.png\n")));
  LiveOptions live;
  LiveViewProvider provider(std::move(cameras), live);
  CHECK_THAT(provider.describe(), Contains("[0: file "));
  CalibrationOptions options;
  options.board = kBoard;
  char floor[32];
  // The plan ends with the three floor views; one sets the world frame here (the default).
  std::snprintf(floor, sizeof floor, "live%05zu", c.plan.size() - 3);
  options.floor_views = {floor};
  std::ostringstream feedback;
  RigCalibrator calibrator(options, &feedback);
  calibrator.add_all(provider);
  const std::string text = feedback.str();
  CHECK_THAT(text, Contains("cam0 live00000: board found; 1 views, coverage"));
  CHECK_THAT(text, Contains("cam7 live00000: no board: no complete grid of "));
  CHECK_THAT(text, Contains(" px; 8 views"));  // the per-view error once the first estimate exists
  const CalibrationResult result = calibrator.solve();
  REQUIRE(result.rig.cameras.size() == ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    INFO("camera " << ids[i]);
    CHECK(result.rig.cameras[i].id == ids[i]);
    CHECK((result.rig.cameras[i].centre() - c.truth.find(ids[i])->centre()).norm() < 100.0);
    CHECK(result.cameras[i].views_kept >= 8);
  }
  CHECK(result.rms_px < 0.4);
}

TEST_CASE("live calibration from a camera whose device is absent fails naming camera and device") {
  const RenderedCapture& c = capture();
  SECTION("v4l2") {
    std::vector<LiveCamera> cameras{live_camera_from_node_config(
        c.node_config(2, "  type: v4l2\n  device: /dev/video-hullpose-absent\n"))};
    CHECK_THROWS_WITH(LiveViewProvider(std::move(cameras), LiveOptions{}),
                      Contains("camera 2: cannot start its v4l2 source") &&
                          Contains("/dev/video-hullpose-absent"));
  }
  SECTION("libcamera") {
    std::vector<LiveCamera> cameras{live_camera_from_node_config(
        c.node_config(4, "  type: libcamera\n  camera: hullpose-absent\n"))};
    CHECK_THROWS_WITH(LiveViewProvider(std::move(cameras), LiveOptions{}),
                      Contains("camera 4: cannot start its libcamera source"));
  }
  SECTION("through the command line") {
    const Process p = run_calibrate(
        "--node-config " +
        c.node_config(0, "  type: v4l2\n  device: /dev/video-hullpose-absent\n").string() +
        " --board 13x8 --square-mm 80 --out " + (c.dir / "never.yaml").string());
    CHECK(p.status == 2);
    CHECK_THAT(p.output, Contains("camera 0: cannot start its v4l2 source"));
  }
  SECTION("a camera missing from the node's rig file") {
    CHECK_THROWS_WITH(
        live_camera_from_node_config(c.node_config(9, "  type: file\n  path: x_%03d.png\n")),
        Contains("camera 9 is not in rig file"));
  }
}
