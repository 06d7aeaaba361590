// End to end on rendered images (issue 9's done-when): a known 8-camera rig, checkerboard images
// rendered through its exact camera model with 0.3 px corner noise, detected with OpenCV,
// calibrated, and compared with the truth; then hulls carved with both rigs.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <iostream>
#include <map>
#include <opencv2/core/utility.hpp>
#include <sstream>

#include "hullpose/calibrate/rig_calibrator.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "synthetic_capture.hpp"

using namespace hullpose;
using namespace hullpose::calibrate;
using namespace hullpose::calibrate::testing;

namespace {

constexpr double kCornerNoisePx = 0.3;  // standard deviation per image axis

struct Detection {
  std::string view;
  int camera = 0;
  cv::Size size;
  std::vector<cv::Point2f> corners;
};

// Rendering and detection are the slow part: done once, shared by the test cases.
struct Capture {
  Rig truth = make_ring_rig(7);
  BoardSpec board{9, 6, 120};
  std::vector<PlannedView> plan;
  std::vector<Detection> detections;
  std::string feedback;

  Capture() {
    plan = make_capture_plan(truth, board, 9, 16, 11);
    const BoardRenderer renderer(truth, board, kCornerNoisePx, 2.0);
    SyntheticViewProvider provider(truth, renderer, plan, 13);
    CaptureInstant instant;
    while (provider.next(instant)) {
      std::vector<std::vector<cv::Point2f>> corners(instant.images.size());
      cv::parallel_for_(cv::Range(0, static_cast<int>(instant.images.size())), [&](const cv::Range& r) {
        for (int i = r.start; i < r.end; ++i)
          corners[static_cast<size_t>(i)] = detect_board(instant.images[static_cast<size_t>(i)].image, board);
      });
      for (size_t i = 0; i < instant.images.size(); ++i)
        detections.push_back({instant.name, instant.images[i].camera_id, instant.images[i].image.size(), corners[i]});
    }
  }

  const PlannedView& planned(const std::string& name) const {
    for (const auto& p : plan)
      if (p.name == name) return p;
    throw std::logic_error("no planned view " + name);
  }
};

const Capture& capture() {
  static const Capture c;
  return c;
}

CalibrationOptions options_for(const Capture& c) {
  CalibrationOptions o;
  o.board = c.board;
  o.rig_id = "calibrated";
  return o;
}

CalibrationResult calibrate_all(const Capture& c, std::ostream* feedback) {
  RigCalibrator calibrator(options_for(c), feedback);
  for (const auto& d : c.detections) calibrator.add_detection(d.view, d.camera, d.size, d.corners);
  return calibrator.solve();
}

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("detected corners lie at the rendered corners, in board order, with the injected noise") {
  const Capture& c = capture();
  double sum2 = 0;
  size_t n = 0, found = 0;
  for (const auto& d : c.detections) {
    if (d.corners.empty()) continue;
    ++found;
    const CameraModel& cam = *c.truth.find(d.camera);
    const auto& pose = c.planned(d.view).world_from_board;
    for (int k = 0; k < c.board.corner_count(); ++k) {
      const auto p = cam.project(pose * c.board.corner_mm(k));
      REQUIRE(p);
      const Eigen::Vector2d e = *p - Eigen::Vector2d(d.corners[static_cast<size_t>(k)].x, d.corners[static_cast<size_t>(k)].y);
      REQUIRE(e.norm() < 3.0);  // a flipped or shifted order would be off by whole squares
      sum2 += e.squaredNorm();
      ++n;
    }
  }
  const double per_axis = std::sqrt(sum2 / (2.0 * static_cast<double>(n)));
  std::cout << "synthetic capture: " << c.detections.size() << " images, board found in " << found
            << ", corner error " << per_axis << " px per axis (injected " << kCornerNoisePx << ")\n";
  CHECK(found >= 100);
  CHECK(per_axis > 0.8 * kCornerNoisePx);
  CHECK(per_axis < 1.3 * kCornerNoisePx);
}

TEST_CASE("the known rig is recovered from rendered checkerboard images") {
  const Capture& c = capture();
  std::ostringstream feedback;
  const CalibrationResult result = calibrate_all(c, &feedback);
  print_report(std::cout, result);
  // Live feedback: one line per image, with coverage, views kept and (once estimated) the error.
  CHECK(feedback.str().find("cam0 a00_close00: board found; 1 views, coverage") != std::string::npos);
  CHECK(feedback.str().find(" px; ") != std::string::npos);

  REQUIRE(result.rig.cameras.size() == c.truth.cameras.size());
  for (size_t i = 0; i < c.truth.cameras.size(); ++i) {
    const CameraModel& t = c.truth.cameras[i];
    const CameraModel& e = result.rig.cameras[i];
    INFO("camera " << t.id);
    REQUIRE(e.id == t.id);
    CHECK(std::abs(e.fx / t.fx - 1) < 0.005);
    CHECK(std::abs(e.fy / t.fy - 1) < 0.005);
    CHECK(std::abs(e.cx - t.cx) < 2.0);
    CHECK(std::abs(e.cy - t.cy) < 2.0);
    CHECK((e.centre() - t.centre()).norm() < 5.0);
    CHECK(angle_deg(e.R, t.R) < 0.2);
    std::cout << "cam" << t.id << ": fx " << 100 * (e.fx / t.fx - 1) << " %, cx " << e.cx - t.cx << " px, cy "
              << e.cy - t.cy << " px, centre " << (e.centre() - t.centre()).norm() << " mm, rotation "
              << angle_deg(e.R, t.R) << " deg\n";
  }
  // RMS at the noise level: the 2D error of noise sigma per axis has RMS sigma * sqrt(2).
  CHECK(result.rms_px > 0.8 * kCornerNoisePx * std::sqrt(2.0));
  CHECK(result.rms_px < 1.2 * kCornerNoisePx * std::sqrt(2.0));
}
