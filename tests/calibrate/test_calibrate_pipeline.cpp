// The calibration pipeline at the corner level (projected corners with Gaussian noise instead of
// rendered images, so each calibration costs seconds): bundle adjustment, recovery of a known
// rig to issue 9's tolerances, live feedback, and the clear errors for bad captures. Several
// full calibrations: too slow for the sanitizer pass, hence "integration".
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "hullpose/calibrate/bundle_adjust.hpp"
#include "hullpose/calibrate/options.hpp"
#include "hullpose/calibrate/rig_calibrator.hpp"
#include "hullpose/common/check.hpp"
#include "synthetic_capture.hpp"

using namespace hullpose;
using namespace hullpose::calibrate;
using namespace hullpose::calibrate::testing;
using Catch::Matchers::Contains;

namespace {

const BoardSpec kBoard{13, 8, 80};
// Lighter than the recommended capture: these tests are about the pipeline, not its accuracy.
const CapturePlan kPlan{.close_ups = 9, .shared = 16, .floors = 3};

struct CornerCapture {
  Rig truth = make_ring_rig(3);
  std::vector<PlannedView> plan = make_capture_plan(truth, kBoard, kPlan, 5);

  // Feeds every planned view's projected corners (noise 0.2 px per axis, 0.28 px RMS) to a
  // calibrator; `keep(view, camera)` can drop observations to build a bad capture.
  template <typename Keep>
  void feed(RigCalibrator& calibrator, Keep keep, unsigned seed = 1) const {
    std::mt19937 rng(seed);
    for (const auto& v : plan)
      for (const auto& c : truth.cameras) {
        auto corners = project_board(c, kBoard, v.world_from_board, 0.2, rng);
        if (!keep(v.name, c.id)) corners.clear();
        calibrator.add_detection(v.name, c.id, {c.width, c.height}, std::move(corners));
      }
  }
};

const CornerCapture& corners() {
  static const CornerCapture c;
  return c;
}

CalibrationOptions default_options() {
  CalibrationOptions o;
  o.board = kBoard;
  o.floor_views = floor_view_names(kPlan);
  return o;
}

std::string solve_error(const RigCalibrator& calibrator) {
  try {
    calibrator.solve();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("bundle adjustment pulls a perturbed rig back to the truth on exact observations") {
  const CornerCapture& cap = corners();
  BundleProblem p;
  for (int k = 0; k < kBoard.corner_count(); ++k) p.board_points.push_back(kBoard.corner_mm(k));
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0, 1);
  const auto floors = floor_view_names(kPlan);
  for (const auto& v : cap.plan) {
    p.world_from_board.push_back(v.world_from_board);
    p.board_motion.push_back(v.name == floors.front() ? BoardMotion::kFixed
                             : std::count(floors.begin(), floors.end(), v.name)
                                 ? BoardMotion::kOnFloor
                                 : BoardMotion::kFree);
  }
  for (size_t c = 0; c < cap.truth.cameras.size(); ++c)
    for (size_t b = 0; b < cap.plan.size(); ++b) {
      const auto pts =
          project_board(cap.truth.cameras[c], kBoard, cap.plan[b].world_from_board, 0.0, rng);
      if (pts.empty()) continue;
      BoardObservation obs;
      obs.camera = static_cast<int>(c);
      obs.board = static_cast<int>(b);
      for (const auto& q : pts) obs.pixels.emplace_back(q.x, q.y);
      p.observations.push_back(obs);
    }
  for (auto cam : cap.truth.cameras) {
    Eigen::Matrix<double, kCameraParams, 1> s;
    s << 0.003 * n(rng), 0.003 * n(rng), 0.003 * n(rng), 20 * n(rng), 20 * n(rng), 20 * n(rng),
        5 * n(rng), 5 * n(rng), 3 * n(rng), 3 * n(rng), 0.01 * n(rng), 0.005 * n(rng),
        1e-4 * n(rng), 1e-4 * n(rng), 0;
    apply_camera_step(cam, s);
    p.cameras.push_back(cam);
  }
  for (size_t b = 0; b < p.world_from_board.size(); ++b) {
    Eigen::Matrix<double, 6, 1> s;
    s << 0.003 * n(rng), 0.003 * n(rng), 0.003 * n(rng), 10 * n(rng), 10 * n(rng), 10 * n(rng);
    // A floor board starts off its true place but on the floor: turned about z, slid in x, y.
    if (p.board_motion[b] == BoardMotion::kOnFloor) s(0) = s(1) = s(5) = 0;
    if (p.board_motion[b] != BoardMotion::kFixed) apply_board_step(p.world_from_board[b], s);
  }
  const BundleResult r = bundle_adjust(p, BundleOptions{});
  CHECK(r.initial_rms_px > 1.0);
  CHECK(r.final_rms_px < 1e-4);
  for (size_t c = 0; c < p.cameras.size(); ++c) {
    CHECK((p.cameras[c].centre() - cap.truth.cameras[c].centre()).norm() < 0.01);
    CHECK(std::abs(p.cameras[c].fx - cap.truth.cameras[c].fx) < 1e-3);
  }
  // The floor boards found their places and stayed flat on the floor throughout.
  int on_floor = 0;
  for (size_t b = 0; b < p.world_from_board.size(); ++b) {
    if (p.board_motion[b] != BoardMotion::kOnFloor) continue;
    ++on_floor;
    const Eigen::Isometry3d& e = p.world_from_board[b];
    CHECK(e.translation().z() == 0);
    CHECK(e.linear().col(2).z() == Approx(-1).margin(1e-12));
    CHECK((e.translation() - cap.plan[b].world_from_board.translation()).norm() < 0.01);
  }
  CHECK(on_floor == 2);
}

TEST_CASE("a known rig is recovered from noisy corners, with the report filled in") {
  RigCalibrator calibrator(default_options());
  corners().feed(calibrator, [](const std::string&, int) { return true; });
  const CalibrationResult r = calibrator.solve();
  const Rig& truth = corners().truth;
  REQUIRE(r.rig.cameras.size() == truth.cameras.size());
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    const auto& t = truth.cameras[i];
    const auto& e = r.rig.cameras[i];
    INFO("camera " << t.id);
    CHECK(std::abs(e.fx / t.fx - 1) < 0.005);
    CHECK(std::abs(e.cx - t.cx) < 2.0);
    CHECK(std::abs(e.cy - t.cy) < 2.0);
    CHECK((e.centre() - t.centre()).norm() < 5.0);
    CHECK(Eigen::AngleAxisd(e.R.transpose() * t.R).angle() * 180 / M_PI < 0.2);
    CHECK(r.cameras[i].views_kept >= 8);
    CHECK(r.cameras[i].coverage > 0.3);
    CHECK(r.cameras[i].rig_rms_px < 0.4);
  }
  CHECK(r.rms_px > 0.2);  // 0.2 px per axis: 0.28 px RMS in 2D
  CHECK(r.rms_px < 0.35);
  // The common view of all cameras: around the middle, from the floor up past head height.
  CHECK(r.rig.volume.min_mm.z() == 0);
  CHECK(r.rig.volume.max_mm.z() > 2000);
  CHECK((r.rig.volume.min_mm.head<2>().array() < -800).all());
  CHECK((r.rig.volume.max_mm.head<2>().array() > 800).all());
}

TEST_CASE("issue 9's tolerances hold for every capture and noise draw, not for one lucky seed") {
  // The rendered-image test's rig and noise (0.3 px RMS), the recommended capture with a
  // different random plan and noise draw each time: eight full calibrations at corner level.
  const Rig truth = make_ring_rig(7);
  const CapturePlan recommended;
  CalibrationOptions options = default_options();
  options.floor_views = floor_view_names(recommended);
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const auto plan = make_capture_plan(truth, kBoard, recommended, 100 + seed);
    RigCalibrator calibrator(options);
    std::mt19937 rng(seed);
    for (const auto& v : plan)
      for (const auto& c : truth.cameras)
        calibrator.add_detection(
            v.name, c.id, {c.width, c.height},
            project_board(c, kBoard, v.world_from_board, 0.3 / std::sqrt(2.0), rng));
    const CalibrationResult r = calibrator.solve();
    const RigError error = compare_rigs(truth, r.rig);
    std::cout << "seed " << seed << ", " << error.worst() << ", floor tilt " << error.gauge_tilt_deg
              << " deg, rms " << r.rms_px << " px\n";
    INFO("seed " << seed);
    for (const auto& e : error.absolute) {
      INFO(e);
      CHECK(meets_issue_tolerances(e));
    }
    // Five floor boards pin the floor's tilt; one board's own tilt, seen from 60 degrees off
    // head-on, was off by up to 0.07 degrees (4 mm at the cameras).
    CHECK(error.gauge_tilt_deg < 0.03);
    CHECK(r.rms_px > 0.27);
    CHECK(r.rms_px < 0.33);
  }
}

TEST_CASE("views with wrong corners, or one misplaced corner, are rejected as outliers") {
  RigCalibrator calibrator(default_options());
  std::mt19937 rng(2);
  const auto& cap = corners();
  for (const auto& v : cap.plan)
    for (const auto& c : cap.truth.cameras) {
      auto pts = project_board(c, kBoard, v.world_from_board, 0.2, rng);
      if (c.id == 2 && v.name == "a02_close04")
        for (size_t k = 0; k < pts.size(); k += 5)
          pts[k] += cv::Point2f(6, -4);  // a few corners far off
      if (c.id == 5 && v.name == "a05_close03" && !pts.empty())
        pts[20] += cv::Point2f(2.5f, -2.0f);  // one corner misplaced: the view's RMS barely moves
      calibrator.add_detection(v.name, c.id, {c.width, c.height}, std::move(pts));
    }
  const CalibrationResult r = calibrator.solve();
  REQUIRE(r.cameras[2].boards_found > 8);
  REQUIRE(r.cameras[2].rejected_views.size() == 1);
  CHECK(r.cameras[2].rejected_views[0] == "a02_close04");
  REQUIRE(r.cameras[5].rejected_views.size() == 1);
  CHECK(r.cameras[5].rejected_views[0] == "a05_close03");
  CHECK(r.rms_px < 0.35);
}

TEST_CASE("a camera that never shares a board view with another fails naming it") {
  RigCalibrator calibrator(default_options());
  // Camera 3 keeps only its own close-ups, and nobody else keeps those.
  corners().feed(calibrator, [](const std::string& view, int cam) {
    const bool cam3_closeup = view.rfind("a03_", 0) == 0;
    return cam == 3 ? cam3_closeup : !cam3_closeup;
  });
  const std::string msg = solve_error(calibrator);
  CHECK_THAT(msg, Contains("camera 3 could not be linked to the rig"));
  CHECK_THAT(msg, Contains("shares 0 board views"));
}

TEST_CASE("bad captures get clear messages, not a rig") {
  SECTION("no board in any image of a camera") {
    RigCalibrator calibrator(default_options());
    corners().feed(calibrator, [](const std::string&, int cam) { return cam != 5; });
    CHECK_THAT(solve_error(calibrator),
               Contains("camera 5: no checkerboard (13x8 inner corners) found in any"));
  }
  SECTION("too few views") {
    RigCalibrator calibrator(default_options());
    int kept = 0;
    corners().feed(calibrator, [&](const std::string& view, int cam) {
      return cam != 6 || (view.rfind("a06_", 0) == 0 && kept++ < 4);
    });
    const std::string msg = solve_error(calibrator);
    CHECK_THAT(msg, Contains("camera 6: board found in only "));
    CHECK_THAT(msg, Contains("need at least 8"));
  }
  SECTION("all views parallel") {
    RigCalibrator calibrator(default_options());
    const CameraModel& cam = corners().truth.cameras[0];
    std::mt19937 rng(3);
    Eigen::Isometry3d cam_from_board = Eigen::Isometry3d::Identity();
    cam_from_board.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()).toRotationMatrix();
    for (int v = 0; v < 12; ++v) {
      cam_from_board.translation() =
          Eigen::Vector3d(-500 + 40 * (v % 4), -300 + 50 * (v / 4), 2000 + 60 * v);
      Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
      world_from_cam.linear() = cam.R.transpose();
      world_from_cam.translation() = cam.centre();
      auto pts = project_board(cam, kBoard, world_from_cam * cam_from_board, 0.2, rng);
      REQUIRE(!pts.empty());
      calibrator.add_detection("v" + std::to_string(v), cam.id, {cam.width, cam.height}, pts);
    }
    CHECK_THAT(solve_error(calibrator),
               Contains("camera 0: all 12 board views are nearly parallel"));
  }
  SECTION("a floor view whose board is not on the floor") {
    CalibrationOptions o = default_options();
    o.floor_views.push_back("b_shared03");  // held up in the middle of the volume
    RigCalibrator calibrator(o);
    corners().feed(calibrator, [](const std::string&, int) { return true; });
    const std::string msg = solve_error(calibrator);
    CHECK_THAT(msg, Contains("the board of floor view 'b_shared03' is "));
    CHECK_THAT(msg, Contains("off the plane of floor view 'floor'"));
  }
  SECTION("a floor view no camera saw") {
    RigCalibrator calibrator(default_options());
    corners().feed(calibrator, [](const std::string& view, int) { return view != "floor3"; });
    CHECK_THAT(solve_error(calibrator),
               Contains("the floor board (instant 'floor3') was not found"));
  }
  SECTION("no floor view") {
    RigCalibrator calibrator(default_options());
    corners().feed(calibrator, [](const std::string& view, int) { return view != "floor"; });
    CHECK_THAT(solve_error(calibrator),
               Contains("the floor board (instant 'floor') was not found"));
  }
  SECTION("wrong board size gives an inconsistent rig") {
    CalibrationOptions o = default_options();
    RigCalibrator calibrator(o);
    std::mt19937 rng(5);
    // Two cameras' corners from a board 5 % larger than declared: the rig cannot agree.
    const auto& cap = corners();
    BoardSpec big = kBoard;
    big.square_mm *= 1.05;
    for (const auto& v : cap.plan)
      for (const auto& c : cap.truth.cameras)
        calibrator.add_detection(
            v.name, c.id, {c.width, c.height},
            project_board(c, c.id < 2 ? big : kBoard, v.world_from_board, 0.2, rng));
    CHECK_THAT(solve_error(calibrator), Contains("the calibrated rig is inconsistent"));
  }
}

TEST_CASE("live feedback reports views, coverage and per-view error as views arrive") {
  std::ostringstream out;
  RigCalibrator calibrator(default_options(), &out);
  corners().feed(calibrator, [](const std::string&, int) { return true; });
  const std::string text = out.str();
  CHECK_THAT(text, Contains("cam0 a00_close00: board found; 1 views, coverage"));
  CHECK_THAT(text, Contains("cam1 a00_close00: no board: no complete grid of "));
  CHECK_THAT(text, Contains(" px; 8 views"));  // the first estimate comes with the 8th view
}
