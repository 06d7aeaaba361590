#pragma once
// Which way a standing subject faces, read from its feet in the hull. The hull of an upright body
// looks nearly the same from the front and from the back, but a foot does not: the leg stands on
// its heel end and the toes reach forward with nothing above them. So, on the floor, the cells
// of each foot whose hull column stays low (toes) lie in front of those that carry a tall column
// (the leg). Used by HullPoseEstimator::acquire_from_hull for a subject that does not travel.
// No allocation once the grid's size has been seen.
#include <Eigen/Core>
#include <vector>

#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"

namespace hullpose::pose {

struct FootFacingParams {
  // Heights above the hull's lowest layer, in statures. A column lower than toe_ratio is a toe
  // (a shoe is ~0.04 statures high at the toes, and the carving adds up to a voxel); one taller
  // than leg_ratio carries a leg (the ankle is ~0.04-0.06 up, the shin goes on to the knee at
  // ~0.28). Columns in between (the instep) say nothing.
  double toe_ratio = 0.05;
  double leg_ratio = 0.15;
  // The toes of the feet together must reach this far beyond their legs (statures; a foot
  // reaches ~0.05-0.09 beyond its shin). Less, and the feet do not say which way is front (a
  // subject on tiptoe, feet under the hull's ghost volume, no feet in the hull).
  double min_reach_ratio = 0.02;
  // Voxels larger than this (statures) do not resolve a toe from an instep: the toes' height must
  // span two voxels. On the thesis rig at 64^3 (53 mm voxels, 0.031 statures) the feet read 131_02
  // backwards in 25 % of the frames they read at all; at 128^3 (0.016) in none.
  double max_voxel_ratio = 0.025;
};

class FootFacing {
 public:
  explicit FootFacing(FootFacingParams params = {}) : params_(params) {}
  // The horizontal direction the feet point (x, y; unit), or false when they do not say (or the
  // voxels are too coarse to).
  // Footprint: the cells set in the hull's lowest layer or the one above it; each 8-connected
  // group of them is a foot and gives (mean of its toe cells) - (mean of its leg cells) when it
  // has at least two of each; the feet's vectors are summed.
  bool measure(const fusion::BitGrid& hull, const VoxelGridSpec& grid, double stature_mm,
               Eigen::Vector2d& facing);

 private:
  FootFacingParams params_;
  // Per (x, y) cell: its column's height in voxels above the lowest layer, or -1 off the
  // footprint; the flood fill's stack.
  std::vector<int> height_, stack_;
};

}  // namespace hullpose::pose
