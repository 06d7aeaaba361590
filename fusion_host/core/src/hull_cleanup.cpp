#include "hullpose/fusion/hull_cleanup.hpp"

#include <algorithm>
#include <bit>

namespace hullpose::fusion {

void HullCleanup::apply(BitGrid& hull, HullStats& stats) {
  stats = HullStats{};
  stats.carved_voxels = hull.count();
  stats.components = labeller_.label(hull);
  if (stats.components > 1) {
    const auto& sizes = labeller_.sizes();
    const auto largest = std::max_element(sizes.begin(), sizes.end()) - sizes.begin();
    keep_.assign(sizes.size(), false);
    for (size_t i = 0; i < sizes.size(); ++i)
      keep_[i] = static_cast<ptrdiff_t>(i) == largest ||
                 (options_.min_component_voxels > 0 && sizes[i] >= options_.min_component_voxels);
    labeller_.extract(keep_, scratch_);
    std::swap(hull, scratch_);  // both buffers keep their capacity: no allocation per frame
    stats.components_kept = static_cast<int>(std::count(keep_.begin(), keep_.end(), true));
  } else {
    stats.components_kept = stats.components;
  }
  stats.voxels_dropped = stats.carved_voxels - hull.count();
  if (options_.max_cavity_voxels > 0)
    stats.cavities_filled = labeller_.fill_cavities(hull, options_.max_cavity_voxels);
  stats.voxels = hull.count();
  // Bounding box from the occupied rows (words), not voxel by voxel.
  const Eigen::Vector3i d = hull.dims();
  for (int z = 0; z < d.z(); ++z)
    for (int y = 0; y < d.y(); ++y) {
      const uint64_t* r = hull.row(y, z);
      for (int w = 0; w < hull.words_per_row(); ++w) {
        if (r[w] == 0) continue;
        const int x0 = w * 64 + std::countr_zero(r[w]), x1 = w * 64 + 63 - std::countl_zero(r[w]);
        if (stats.bbox_max.x() < 0) {
          stats.bbox_min = {x0, y, z};
          stats.bbox_max = {x1, y, z};
        }
        stats.bbox_min = stats.bbox_min.cwiseMin(Eigen::Vector3i(x0, y, z));
        stats.bbox_max = stats.bbox_max.cwiseMax(Eigen::Vector3i(x1, y, z));
      }
    }
}

}  // namespace hullpose::fusion
