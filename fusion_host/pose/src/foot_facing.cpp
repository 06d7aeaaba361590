#include "hullpose/pose/foot_facing.hpp"

#include <algorithm>

namespace hullpose::pose {

bool FootFacing::measure(const fusion::BitGrid& hull, const VoxelGridSpec& grid, double stature_mm,
                         Eigen::Vector2d& facing) {
  const Eigen::Vector3i d = hull.dims();
  if (d.minCoeff() <= 0 || grid.voxel_mm <= 0 ||
      grid.voxel_mm > params_.max_voxel_ratio * stature_mm)
    return false;
  const int wpr = hull.words_per_row();
  auto layer_empty = [&](int z) {
    for (int y = 0; y < d.y(); ++y) {
      const uint64_t* r = hull.row(y, z);
      for (int w = 0; w < wpr; ++w)
        if (r[w] != 0) return false;
    }
    return true;
  };
  int z0 = 0;
  while (z0 < d.z() && layer_empty(z0)) ++z0;
  if (z0 == d.z()) return false;

  const size_t cells = static_cast<size_t>(d.x()) * d.y();
  if (height_.size() < cells) {  // a larger grid: once
    height_.resize(cells);
    stack_.resize(cells);
  }
  std::fill(height_.begin(), height_.begin() + static_cast<std::ptrdiff_t>(cells), -1);
  for (int y = 0; y < d.y(); ++y)
    for (int x = 0; x < d.x(); ++x) {
      int z = hull.get(x, y, z0) ? z0 : z0 + 1;
      if (!hull.get_or_zero(x, y, z)) continue;
      while (hull.get_or_zero(x, y, z + 1)) ++z;
      height_[static_cast<size_t>(y) * d.x() + x] = z - z0;
    }

  const double toe = params_.toe_ratio * stature_mm / grid.voxel_mm;
  const double leg = params_.leg_ratio * stature_mm / grid.voxel_mm;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (size_t seed = 0; seed < cells; ++seed) {
    if (height_[seed] < 0) continue;
    // One foot: the 8-connected footprint cells around `seed`. A cell taken into the fill is
    // marked -2 - height (so off the footprint is -1, taken is below it, and the height is kept).
    Eigen::Vector2d toe_sum = Eigen::Vector2d::Zero(), leg_sum = Eigen::Vector2d::Zero();
    int toes = 0, legs = 0;
    size_t top = 0;
    auto take = [&](size_t i) {
      height_[i] = -2 - height_[i];
      stack_[top++] = static_cast<int>(i);
    };
    take(seed);
    while (top > 0) {
      const size_t i = static_cast<size_t>(stack_[--top]);
      const int h = -2 - height_[i], x = static_cast<int>(i % d.x()),
                y = static_cast<int>(i / d.x());
      const Eigen::Vector2d c = grid.centre_mm({x, y, z0}).head<2>();
      if (h < toe) {
        toe_sum += c;
        ++toes;
      } else if (h > leg) {
        leg_sum += c;
        ++legs;
      }
      for (int ny = std::max(y - 1, 0); ny <= std::min(y + 1, d.y() - 1); ++ny)
        for (int nx = std::max(x - 1, 0); nx <= std::min(x + 1, d.x() - 1); ++nx) {
          const size_t n = static_cast<size_t>(ny) * d.x() + nx;
          if (height_[n] >= 0) take(n);
        }
    }
    if (toes >= 2 && legs >= 2) sum += toe_sum / toes - leg_sum / legs;
  }
  if (sum.norm() < params_.min_reach_ratio * stature_mm) return false;
  facing = sum.normalized();
  return true;
}

}  // namespace hullpose::pose
