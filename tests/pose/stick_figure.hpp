#pragma once
// Test fixtures: stick figures of the 25-joint model in chosen poses, and their bones
// rasterised into curve-skeleton voxels (what a perfect thinning of a thin body would give).
#include <Eigen/Geometry>
#include <algorithm>
#include <random>
#include <vector>

#include "hullpose/common/joints.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/pose/model_fit.hpp"

namespace hullpose::pose::test {

// Limb directions in the body frame: x = the subject's left, y = forward, z = up.
struct Limbs {
  Eigen::Vector3d l_upper_arm{1, 0, 0}, l_forearm{1, 0, 0};
  Eigen::Vector3d r_upper_arm{-1, 0, 0}, r_forearm{-1, 0, 0};
  Eigen::Vector3d l_thigh{0, 0, -1}, l_shin{0, 0, -1};
  Eigen::Vector3d r_thigh{0, 0, -1}, r_shin{0, 0, -1};
};

inline Limbs t_pose() {
  return {};
}
// Mid-stride: arms swinging, one leg forward (test_model_fit, bench_pose).
inline Limbs walking() {
  Limbs walk = t_pose();
  walk.l_upper_arm = {0.2, 0.4, -1};
  walk.l_forearm = {0.1, 0.8, -0.6};
  walk.r_upper_arm = {-0.2, -0.4, -1};
  walk.r_forearm = {-0.1, 0.2, -1};
  walk.l_thigh = {0, 0.5, -1};
  walk.l_shin = {0, -0.1, -1};
  walk.r_thigh = {0, -0.3, -1};
  walk.r_shin = {0, -0.6, -1};
  return walk;
}

// World placement: the body frame turned by `yaw_deg` about z (0: facing +y, left = -x), then
// by `roll_deg` about the facing direction (180: upside down), the lowest joint 40 mm above
// the floor at (x, y).
struct Placement {
  double yaw_deg = 0, roll_deg = 0;
  double x_mm = 0, y_mm = 0;
};

inline JointPositions stick_figure(double stature, const Limbs& limbs, const Placement& at = {}) {
  using V = Eigen::Vector3d;
  auto len = [&](Joint child) {
    for (const Bone& b : kBones)
      if (b.child == child) return b.stature_ratio * stature;
    return 0.0;
  };
  JointPositions b;  // body frame
  auto J = [&](Joint j) -> V& { return b[index(j)]; };
  J(Joint::LBack) = V(0, 0, 0);
  J(Joint::Back) = J(Joint::LBack) + V(0, 0, len(Joint::LBack));
  J(Joint::UBack) = J(Joint::Back) + V(0, 0, len(Joint::Back));
  J(Joint::Chest) = J(Joint::UBack) + V(0, 0, len(Joint::UBack));
  J(Joint::Neck) = J(Joint::Chest) + V(0, 0, len(Joint::Neck));
  J(Joint::Head) = J(Joint::Neck) + V(0, 0, len(Joint::Head));
  J(Joint::HeadTop) = J(Joint::Head) + V(0, 0, len(Joint::HeadTop));
  J(Joint::LSho) = J(Joint::Chest) + len(Joint::LSho) * V(0.978, 0, 0.207).normalized();
  J(Joint::RSho) = J(Joint::Chest) + len(Joint::RSho) * V(-0.978, 0, 0.207).normalized();
  J(Joint::LElb) = J(Joint::LSho) + len(Joint::LElb) * limbs.l_upper_arm.normalized();
  J(Joint::RElb) = J(Joint::RSho) + len(Joint::RElb) * limbs.r_upper_arm.normalized();
  J(Joint::LHand) = J(Joint::LElb) + len(Joint::LHand) * limbs.l_forearm.normalized();
  J(Joint::RHand) = J(Joint::RElb) + len(Joint::RHand) * limbs.r_forearm.normalized();
  J(Joint::LFTip) = J(Joint::LHand) + len(Joint::LFTip) * limbs.l_forearm.normalized();
  J(Joint::RFTip) = J(Joint::RHand) + len(Joint::RFTip) * limbs.r_forearm.normalized();
  J(Joint::LHip) = J(Joint::LBack) + len(Joint::LHip) * V(0.643, 0.295, -0.707).normalized();
  J(Joint::RHip) = J(Joint::LBack) + len(Joint::RHip) * V(-0.643, 0.295, -0.707).normalized();
  J(Joint::LKne) = J(Joint::LHip) + len(Joint::LKne) * limbs.l_thigh.normalized();
  J(Joint::RKne) = J(Joint::RHip) + len(Joint::RKne) * limbs.r_thigh.normalized();
  J(Joint::LAnk) = J(Joint::LKne) + len(Joint::LAnk) * limbs.l_shin.normalized();
  J(Joint::RAnk) = J(Joint::RKne) + len(Joint::RAnk) * limbs.r_shin.normalized();
  const V foot = V(0, 0.992, -0.127).normalized();
  J(Joint::LFoot) = J(Joint::LAnk) + len(Joint::LFoot) * foot;
  J(Joint::RFoot) = J(Joint::RAnk) + len(Joint::RFoot) * foot;
  J(Joint::LToe) = J(Joint::LFoot) + len(Joint::LToe) * V(0, 1, 0);
  J(Joint::RToe) = J(Joint::RFoot) + len(Joint::RToe) * V(0, 1, 0);

  // Body frame -> world: facing +y means left = -x.
  const double deg = M_PI / 180;
  const Eigen::Matrix3d to_world_axes =
      (Eigen::Matrix3d() << -1, 0, 0, 0, 1, 0, 0, 0, 1).finished();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(at.yaw_deg * deg, V::UnitZ()).toRotationMatrix() *
                            Eigen::AngleAxisd(at.roll_deg * deg, V::UnitY()).toRotationMatrix() *
                            to_world_axes;
  JointPositions w;
  double min_z = 1e9;
  for (int j = 0; j < kNumJoints; ++j) {
    w[j] = R * b[j];
    min_z = std::min(min_z, w[j].z());
  }
  for (auto& p : w) p += V(at.x_mm, at.y_mm, 40 - min_z);
  return w;
}

inline VoxelGridSpec grid_2m(int resolution) {
  CaptureVolume v;
  v.min_mm = Eigen::Vector3d(-1000, -1000, 0);
  v.max_mm = Eigen::Vector3d(1000, 1000, 2000);
  return VoxelGridSpec::fit(v, resolution);
}

// Room for a hand raised above the head (the 2 m grid would cut it off, and a skeleton cut off
// by the volume is invalid).
inline VoxelGridSpec grid_tall(int resolution) {
  CaptureVolume v;
  v.min_mm = Eigen::Vector3d(-1200, -1200, 0);
  v.max_mm = Eigen::Vector3d(1200, 1200, 2400);
  return VoxelGridSpec::fit(v, resolution);
}

inline Eigen::Vector3i voxel_of(const VoxelGridSpec& g, const Eigen::Vector3d& p) {
  return ((p - g.origin_mm) / g.voxel_mm).array().floor().cast<int>().matrix();
}

// Voxels along segments, sampled at a quarter voxel, duplicates removed.
inline void rasterise_segment(const VoxelGridSpec& g, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, std::vector<Eigen::Vector3i>& out) {
  const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (g.voxel_mm / 4))));
  for (int s = 0; s <= steps; ++s) {
    const Eigen::Vector3i v = voxel_of(g, a + (b - a) * (static_cast<double>(s) / steps));
    if (g.contains(v)) out.push_back(v);
  }
}

inline void dedupe(std::vector<Eigen::Vector3i>& v) {
  auto less = [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

inline std::vector<Eigen::Vector3i> rasterise(const VoxelGridSpec& g,
                                              const JointPositions& joints) {
  std::vector<Eigen::Vector3i> out;
  for (const Bone& b : kBones)
    rasterise_segment(g, joints[index(b.parent)], joints[index(b.child)], out);
  dedupe(out);
  return out;
}

// Adds `count` short spurious branches (2..max_voxels long) at random skeleton voxels, in
// random directions: the noise thinning leaves on a real hull.
inline void add_spurs(const VoxelGridSpec& g, std::vector<Eigen::Vector3i>& voxels, int count,
                      int max_voxels, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, voxels.size() - 1);
  std::uniform_int_distribution<int> length(2, max_voxels);
  std::normal_distribution<double> n01;
  const size_t n = voxels.size();
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3d start = g.centre_mm(voxels[pick(rng) % n]);
    // Drawn one by one: the order of a call's arguments is unspecified (GCC takes them right to
    // left on x86-64, left to right on aarch64), so Vector3d(n01(rng), n01(rng), n01(rng)) made
    // other spurs on each. z, y, x keeps the data this test was written with on x86-64.
    const double dz = n01(rng), dy = n01(rng), dx = n01(rng);
    const Eigen::Vector3d dir = Eigen::Vector3d(dx, dy, dz).normalized();
    rasterise_segment(g, start, start + dir * length(rng) * g.voxel_mm, voxels);
  }
  dedupe(voxels);
}

}  // namespace hullpose::pose::test
