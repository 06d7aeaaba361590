#pragma once
// Volumetric visual hull of one trigger instant.
//
// Definition (what both the fast path and the brute-force reference compute):
//   the pixel of voxel v in camera c is (round(u), round(v)) of VoxelProjector::project(centre of
//   v), i.e. the pixel whose centre is nearest to the projected voxel centre (OpenCV pixel centres
//   are integer coordinates; halves round up). The voxel centre "projects inside the
//   silhouette" iff it is in front of the camera, that pixel lies in the image, and the mask is
//   non-zero there. A voxel is kept iff it misses (does not project inside) in at most
//   `tolerance` (k) of the cameras that delivered a silhouette this instant ("all but k").
//   Cameras that sent nothing (empty cv::Mat), or sent a mask of the wrong size or type, are
//   skipped and reported; with no more than k cameras present the hull is empty and not valid.
//
// Fast path (hierarchical, conservative, exact): per rig and resolution, the Carver projects
// every voxel centre once and stores, for the nodes of a 4-level octree of voxel blocks (4³
// voxels and up), the bounding rectangle of the pixels of their voxel centres in every camera.
// Per frame it counts, down each column of each silhouette's foreground box, the foreground
// pixels (ColumnCounts), then classifies nodes per camera as all inside (the rectangle is all
// foreground), all outside (no foreground) or mixed, counts misses and only descends into nodes
// that are still undecided. Voxels of undecided finest nodes are tested camera by camera at
// their pixel, read from a per-voxel table computed at construction with the same projection as
// the reference (2 bytes per voxel and camera, up to 64 MiB: 128³ with 8 cameras), or projected
// on the fly beyond that. Either way the result equals carve_brute_force() voxel for voxel by
// construction (checked in tests/fusion/test_carve, test_carve_large and test_cmu at 64³, 128³
// and 256³). Resolutions up to 575.
//
// Lifecycle: construct once per (rig, resolution, tolerance); carve() per frame reuses all
// buffers (no allocation at steady state).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <span>
#include <vector>

#include "hullpose/carve/voxel_test.hpp"
#include "hullpose/common/camera.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/common/silhouette_codec.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"

namespace hullpose::carve {

// World point -> nearest pixel, the single definition shared by the fast path, the reference
// and the CUDA backend (voxel_test.hpp). Same model as CameraModel::project.
class VoxelProjector {
 public:
  VoxelProjector() = default;
  explicit VoxelProjector(const CameraModel& camera);
  // False if the point is not in front of the camera or its pixel is outside the image.
  bool pixel(const Eigen::Vector3d& world, int& px, int& py) const {
    return project_to_pixel(params_, world.x(), world.y(), world.z(), px, py);
  }
  int width() const { return params_.width; }
  int height() const { return params_.height; }
  const CameraParams& params() const { return params_; }

 private:
  CameraParams params_;
};

// The part of view `camera` that carving reads: fg_boxes[camera] clipped to the image when
// foreground boxes are given (pixels outside it are background), else the mask's bounding box of
// non-zero pixels. Shared by the CPU fast path and the CUDA upload.
cv::Rect foreground_box(const cv::Mat& view, std::span<const PixelRoi> fg_boxes, size_t camera);

struct CarveOptions {
  int resolution = 64;  // voxels along the longest axis of the capture volume
  int tolerance = 0;    // k: a voxel may miss the silhouette in up to k present cameras
  int threads = 1;      // OpenMP threads for carve()
};

// Per-frame outcome. Reuse one instance across frames (its vectors keep their capacity).
struct CarveReport {
  bool valid = false;  // more than `tolerance` cameras present
  int cameras_used = 0;
  std::vector<int> missing_cameras;   // camera ids that sent nothing
  std::vector<int> rejected_cameras;  // camera ids whose mask had the wrong size or type
  size_t voxels = 0;                  // voxels in the hull
};

class Carver {
 public:
  // Precomputes per camera the projections of the grid (cost ~ voxels x cameras projections).
  // Throws hullpose::Error on a bad resolution or tolerance.
  Carver(const Rig& rig, const CarveOptions& options);
  ~Carver();
  Carver(const Carver&) = delete;
  Carver& operator=(const Carver&) = delete;

  const VoxelGridSpec& grid() const { return grid_; }
  const CarveOptions& options() const { return options_; }

  // views[i] is the silhouette of rig.cameras[i] (CV_8UC1, non-zero = foreground, the camera's
  // size) or an empty Mat if that camera sent nothing. fg_boxes, if not empty, holds per view the
  // bounding box of its foreground (e.g. the silhouette codec's ROI); pixels outside it must be
  // background. Without it the box is computed. `hull` is resized to the grid.
  void carve(std::span<const cv::Mat> views, fusion::BitGrid& hull, CarveReport& report,
             std::span<const PixelRoi> fg_boxes = {});

  // Reference: every voxel centre projected into every present camera (tests, benchmarks).
  void carve_brute_force(std::span<const cv::Mat> views, fusion::BitGrid& hull,
                         CarveReport& report) const;

  // The start of every carve, shared with the CUDA backend: which views are usable (fills the
  // report's camera lists and validity, and `present` with the indices of the usable views) and
  // `hull` cleared to the grid. False when too few views are usable: nothing to carve. Throws on
  // a wrong number of views or of foreground boxes.
  bool begin_carve(std::span<const cv::Mat> views, std::span<const PixelRoi> fg_boxes,
                   fusion::BitGrid& hull, CarveReport& report, std::vector<int>& present) const;
  const std::vector<VoxelProjector>& projectors() const { return projectors_; }

 private:
  struct Precomputed;
  struct Frame;
  class NodeVisit;

  Rig rig_;
  CarveOptions options_;
  VoxelGridSpec grid_;
  std::vector<VoxelProjector> projectors_;
  std::unique_ptr<Precomputed> pre_;
  std::unique_ptr<Frame> frame_;
};

}  // namespace hullpose::carve
