#pragma once
// The voxel grid over the rig's capture volume, shared by carving, thinning and the pose
// stages. Voxels are cubes; the longest axis of the capture volume gets `resolution` voxels,
// the others as many as fit (rounded up), and the grid is centred on the volume.
// Linear index: x fastest, then y, then z.
#include <Eigen/Core>
#include <cstddef>

#include "hullpose/common/rig.hpp"

namespace hullpose {

struct VoxelGridSpec {
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();       // voxels along x, y, z
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();  // min corner of voxel (0,0,0)
  double voxel_mm = 0;                                  // edge length

  static VoxelGridSpec fit(const CaptureVolume& volume, int resolution);

  size_t size() const { return static_cast<size_t>(dims.x()) * dims.y() * dims.z(); }
  size_t index(int x, int y, int z) const {
    return (static_cast<size_t>(z) * dims.y() + y) * dims.x() + x;
  }
  bool contains(const Eigen::Vector3i& v) const {
    return (v.array() >= 0).all() && (v.array() < dims.array()).all();
  }
  Eigen::Vector3d centre_mm(const Eigen::Vector3i& v) const {
    return origin_mm + (v.cast<double>().array() + 0.5).matrix() * voxel_mm;
  }
  bool operator==(const VoxelGridSpec&) const = default;
};

}  // namespace hullpose
