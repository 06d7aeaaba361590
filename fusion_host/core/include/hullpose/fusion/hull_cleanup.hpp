#pragma once
// Clean-up of a carved hull before thinning: keep the person's component(s), fill small
// cavities (a cavity would force a closed surface into the skeleton), and hull statistics.
#include <Eigen/Core>
#include <cstdint>

#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/thin/topology_stats.hpp"

namespace hullpose::fusion {

struct CleanupOptions {
  // 0: keep only the largest 26-connected component; > 0: keep every component of at least
  // this many voxels (the largest is always kept).
  int64_t min_component_voxels = 0;
  int64_t max_cavity_voxels = 512;  // fill enclosed background components up to this size; 0 = off
};

struct HullStats {
  size_t carved_voxels = 0;  // before clean-up
  size_t voxels = 0;         // after
  int components = 0;        // 26-components before clean-up
  int components_kept = 0;
  size_t voxels_dropped = 0;  // in the components removed
  int cavities_filled = 0;
  Eigen::Vector3i bbox_min = Eigen::Vector3i::Zero(),
                  bbox_max = Eigen::Vector3i::Constant(-1);  // inclusive
};

class HullCleanup {
 public:
  explicit HullCleanup(const CleanupOptions& options = {}) : options_(options) {}
  // Cleans `hull` in place and fills `stats`.
  void apply(BitGrid& hull, HullStats& stats);

 private:
  CleanupOptions options_;
  thin::ComponentLabeller labeller_;
  std::vector<bool> keep_;
  BitGrid scratch_;
};

}  // namespace hullpose::fusion
