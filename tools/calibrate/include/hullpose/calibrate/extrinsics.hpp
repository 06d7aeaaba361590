#pragma once
// First estimate of the rig's extrinsics: each camera's board poses (from its intrinsic
// calibration) are chained through capture instants in which two cameras saw the same board,
// along a maximum spanning tree of the camera graph (edge weight = shared views), then the
// common view of the calibrated cameras gives the capture volume.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "hullpose/common/camera.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::calibrate {

struct PoseObservation {
  int camera = 0;  // index 0..n_cameras-1
  int view = 0;    // index 0..n_views-1
  Eigen::Isometry3d cam_from_board = Eigen::Isometry3d::Identity();
  double rms_px = 0;
};

struct Linkage {
  std::vector<bool> linked;                      // per camera: reached from the root
  std::vector<Eigen::Isometry3d> root_from_cam;  // per camera (identity where not linked)
  std::vector<std::optional<Eigen::Isometry3d>>
      root_from_board;            // per view seen by a linked camera
  std::vector<int> shared_views;  // per camera: views shared with any other camera
};

Linkage link_cameras(int n_cameras, int n_views, const std::vector<PoseObservation>& observations,
                     int root_camera);

// Axis-aligned box around the points (sampled every step_mm over the cameras' horizontal extent
// grown by half its size on every side, from the floor up to the highest camera) that at least
// `min_cameras` cameras see inside their image. Throws hullpose::Error if no such point exists.
CaptureVolume common_view_volume(const std::vector<CameraModel>& cameras, int min_cameras,
                                 double step_mm = 100);

}  // namespace hullpose::calibrate
