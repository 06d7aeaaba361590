#pragma once
// Joint refinement of a whole rig over all checkerboard observations: every camera's pose and,
// optionally, its intrinsics, plus every board pose (one per capture instant), minimising the
// squared reprojection error with Levenberg-Marquardt.
//
// Why hand-written: OpenCV 4.6 has no multi-camera bundle adjustment (stereoCalibrate pairs two
// cameras, detail::BundleAdjuster* is rotation-only for panoramas) and Ceres is not a dependency.
// The problem is small and has the classic BA structure, so this is Eigen with analytic Jacobians
// and a Schur complement over the 6x6 board blocks: the reduced system has only
// (cameras x camera parameters) unknowns and is solved densely.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "hullpose/common/camera.hpp"

namespace hullpose::calibrate {

// Camera parameter block: rotation increment (3, left-multiplied), t (3), fx fy cx cy, k1 k2 p1 p2
// k3.
constexpr int kCameraParams = 15;
using CameraJacobian = Eigen::Matrix<double, 2, kCameraParams>;
// Board parameter block: rotation increment (3, left-multiplied), translation (3).
using BoardJacobian = Eigen::Matrix<double, 2, 6>;

struct BoardObservation {
  int camera = 0;                       // index into BundleProblem::cameras
  int board = 0;                        // index into BundleProblem::world_from_board
  std::vector<Eigen::Vector2d> pixels;  // one per board point, same order
};

// How a board may move. The world frame (the gauge) needs at least one fixed board.
enum class BoardMotion {
  kFree,
  // Lying on the world's z = const plane it starts on: it only slides along x and y and turns
  // about z. Several boards laid on the floor then define the floor plane together, instead of
  // the tilt of a single board fixing it for the whole rig.
  kOnFloor,
  kFixed,
};

struct BundleProblem {
  std::vector<Eigen::Vector3d> board_points;  // board frame, mm
  std::vector<CameraModel> cameras;           // initial values; refined in place
  std::vector<Eigen::Isometry3d> world_from_board;
  std::vector<BoardMotion> board_motion;  // per board
  std::vector<BoardObservation> observations;
};

struct BundleOptions {
  bool refine_intrinsics = true;
  bool refine_k3 = true;
  int max_iterations = 100;
};

struct BundleResult {
  int iterations = 0;
  double initial_rms_px = 0;
  double final_rms_px = 0;
  std::vector<double> camera_rms_px;  // per camera, over its observations
  std::vector<int> camera_corners;    // corners observed per camera
};

// Throws hullpose::Error if the problem is malformed (no fixed board, a point behind a camera at
// the start); the LM iterations themselves never make the cost worse.
BundleResult bundle_adjust(BundleProblem& problem, const BundleOptions& options);

// Pixel of board point `X` on board `world_from_board` seen by `camera`, with the Jacobians with
// respect to the camera block and the board block (either may be null). False if the point is not
// in front of the camera.
bool project_with_jacobians(const CameraModel& camera, const Eigen::Isometry3d& world_from_board,
                            const Eigen::Vector3d& X, Eigen::Vector2d& pixel, CameraJacobian* jc,
                            BoardJacobian* jb);

// Applies a parameter increment (the block layouts above); exposed for the Jacobian tests.
void apply_camera_step(CameraModel& camera, const Eigen::Matrix<double, kCameraParams, 1>& step);
void apply_board_step(Eigen::Isometry3d& world_from_board, const Eigen::Matrix<double, 6, 1>& step);

}  // namespace hullpose::calibrate
