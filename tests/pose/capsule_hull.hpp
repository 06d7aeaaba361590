#pragma once
// Test fixture: the hull of a stick figure's body, the union of the body model's capsules
// around its bones (body_model.hpp) voxelised into a BitGrid: what carving from many views of
// a body made of capsules would give.
#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/pose/body_model.hpp"
#include "stick_figure.hpp"

namespace hullpose::pose::test {

inline double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t =
      ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Capsules of `model` around the bones of `joints`; bones listed in `skip` are left out (a limb
// the hull does not show apart from the body).
inline void capsule_hull(const VoxelGridSpec& g, const JointPositions& joints,
                         const BodyModel& model, fusion::BitGrid& out,
                         std::initializer_list<int> skip = {}) {
  out.reset(g.dims);
  for (int b = 0; b < kNumBones; ++b) {
    if (std::find(skip.begin(), skip.end(), b) != skip.end()) continue;
    const Eigen::Vector3d& a = joints[index(kBones[b].parent)];
    const double r = model.radius_mm[b];
    const Eigen::Vector3d c = capsule_end(b, a, joints[index(kBones[b].child)], r);
    const Eigen::Vector3i lo = voxel_of(g, a.cwiseMin(c).array() - r).cwiseMax(0);
    const Eigen::Vector3i hi =
        voxel_of(g, a.cwiseMax(c).array() + r).cwiseMin(g.dims - Eigen::Vector3i::Ones());
    for (int z = lo.z(); z <= hi.z(); ++z)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int x = lo.x(); x <= hi.x(); ++x)
          if (segment_distance(g.centre_mm({x, y, z}), a, c) <= r) out.set(x, y, z);
  }
}

// Mean joint distance (mm).
inline double mean_error(const JointPositions& a, const JointPositions& b) {
  double s = 0;
  for (int j = 0; j < kNumJoints; ++j) s += (a[j] - b[j]).norm();
  return s / kNumJoints;
}

}  // namespace hullpose::pose::test
