// Calibration against another tool's rig: extrinsics with known intrinsics from one floor view
// per camera, and the comparison of two calibrations whose world frames differ.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "hullpose/calibrate/rig_calibrator.hpp"
#include "hullpose/calibrate/rig_compare.hpp"
#include "hullpose/synth/rig_gen.hpp"

using namespace hullpose;
using namespace hullpose::calibrate;
using Catch::Contains;

namespace {

Rig four_cameras() {
  synth::RingRigSpec spec;
  spec.ring_cameras = 4;
  spec.ceiling = false;
  spec.k1 = -0.05;
  return synth::make_ring_rig(spec);
}

// The board lying printed face up with its corner grid's centre at the world origin (the
// calibrator's world frame), seen by `c`.
std::vector<cv::Point2f> floor_corners(const CameraModel& c, const BoardSpec& board) {
  Eigen::Isometry3d world_from_board = Eigen::Isometry3d::Identity();
  world_from_board.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  world_from_board.translation() = -(world_from_board.linear() * board.centre_mm());
  std::vector<cv::Point2f> out;
  for (int i = 0; i < board.corner_count(); ++i) {
    const auto px = c.project(world_from_board * board.corner_mm(i));
    REQUIRE(px);
    out.emplace_back(static_cast<float>(px->x()), static_cast<float>(px->y()));
  }
  return out;
}

}  // namespace

TEST_CASE("with known intrinsics one floor view per camera gives the extrinsics") {
  const Rig truth = four_cameras();
  CalibrationOptions o;
  o.board = {9, 6, 115};
  for (const CameraModel& c : truth.cameras) o.known_intrinsics[c.id] = c;
  RigCalibrator calibrator(o);
  for (const CameraModel& c : truth.cameras)
    calibrator.add_detection("floor", c.id, {c.width, c.height}, floor_corners(c, o.board));
  const CalibrationResult r = calibrator.solve();
  CHECK(r.rms_px < 0.01);
  for (const CameraModel& c : truth.cameras) {
    const CameraModel* got = r.rig.find(c.id);
    REQUIRE(got);
    INFO("camera " << c.id << " got " << got->centre().transpose() << " truth "
                   << c.centre().transpose());
    CHECK((got->centre() - c.centre()).norm() < 0.5);
    CHECK(Eigen::AngleAxisd(got->R * c.R.transpose()).angle() < 1e-4);
    CHECK(got->fx == c.fx);  // kept
  }
  const RigDifference d = compare_rigs(r.rig, truth);
  CHECK(d.frame_rotation_deg < 0.01);
  for (const CameraDifference& c : d.cameras) CHECK(c.centre_mm < 0.5);
}

TEST_CASE("two calibrations in different world frames compare camera by camera") {
  const Rig a = four_cameras();
  // b: the same rig in a frame turned 30 degrees and shifted (another tool's origin), camera 2
  // moved by 12 mm and turned by 0.3 degrees, its focal length 1 % longer.
  Eigen::Isometry3d b_from_a = Eigen::Isometry3d::Identity();
  b_from_a.linear() = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  b_from_a.translation() = Eigen::Vector3d(400, -300, 0);
  Rig b = a;
  for (CameraModel& c : b.cameras) {
    const Eigen::Vector3d centre = b_from_a * c.centre();
    c.R = c.R * b_from_a.linear().transpose();
    c.t = -c.R * centre;
    if (c.id == 2) {
      const Eigen::Vector3d moved = centre + Eigen::Vector3d(12, 0, 0);
      c.R = Eigen::AngleAxisd(0.3 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() * c.R;
      c.t = -c.R * moved;
      c.fx *= 1.01;
      c.fy *= 1.01;
    }
  }
  const RigDifference d = compare_rigs(a, b);
  CHECK(d.frame_rotation_deg == Approx(30).margin(0.2));
  REQUIRE(d.cameras.size() == 4);
  for (const CameraDifference& c : d.cameras) {
    if (c.id == 2) {
      CHECK(c.centre_mm > 6);  // the alignment spreads the 12 mm over the four cameras
      CHECK(c.orientation_deg == Approx(0.3).margin(0.05));
      CHECK(c.focal_pct == Approx(-1 / 1.01).margin(0.01));
    } else {
      CHECK(c.centre_mm < 6);
      CHECK(c.orientation_deg < 0.05);
    }
  }
  Rig two = a;
  two.cameras.resize(2);
  CHECK_THROWS_WITH(compare_rigs(two, b), Contains("need 3 or more"));
}
