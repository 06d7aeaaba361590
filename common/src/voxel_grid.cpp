#include "hullpose/common/voxel_grid.hpp"

#include <cmath>

#include "hullpose/common/check.hpp"

namespace hullpose {

VoxelGridSpec VoxelGridSpec::fit(const CaptureVolume& volume, int resolution) {
  HULLPOSE_THROW_UNLESS(resolution >= 8 && resolution <= 1024,
                        "voxel resolution " << resolution << " must be in 8..1024");
  const Eigen::Vector3d size = volume.size_mm();
  HULLPOSE_THROW_UNLESS((size.array() > 0).all(), "capture volume must have positive size");
  VoxelGridSpec g;
  g.voxel_mm = size.maxCoeff() / resolution;
  for (int a = 0; a < 3; ++a)
    g.dims[a] = std::min(resolution, static_cast<int>(std::ceil(size[a] / g.voxel_mm - 1e-9)));
  const Eigen::Vector3d extent = g.dims.cast<double>() * g.voxel_mm;
  g.origin_mm = volume.min_mm + (size - extent) / 2;
  return g;
}

}  // namespace hullpose
