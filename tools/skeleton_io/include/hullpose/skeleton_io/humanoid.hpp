#pragma once
// The pose as Unity humanoid bones (HumanBodyBones names, as the VMC protocol sends them): each
// bone's local rotation relative to its humanoid parent from a T-pose rest, and its local
// position, in Unity's frame (left-handed, Y up, metres; the avatar faces +Z with its left on -X).
// Built on BvhSkeleton's rotations, so the BVH export, the BVH stream and VMC agree.
#include <Eigen/Geometry>
#include <array>
#include <string_view>
#include <vector>

#include "hullpose/skeleton_io/bvh.hpp"

namespace hullpose::skeleton_io {

struct HumanoidBone {
  std::string_view name;        // Unity HumanBodyBones name
  Eigen::Vector3d position;     // m: Hips in the world, the others from their humanoid parent
  Eigen::Quaterniond rotation;  // local, from the T-pose
};

inline constexpr int kNumHumanoidBones = 19;

class HumanoidMap {
 public:
  explicit HumanoidMap(const BvhSkeleton& skeleton);
  // Fills `out` (kNumHumanoidBones entries) for one pose.
  void pose(const JointPositions& joints_mm,
            std::array<HumanoidBone, kNumHumanoidBones>& out) const;

 private:
  struct Entry {
    std::string_view name;
    int node;    // BvhSkeleton node whose rotation the bone takes
    int parent;  // index into entries_, -1 for Hips
  };
  const BvhSkeleton& skeleton_;
  std::array<Entry, kNumHumanoidBones> entries_{};
};

}  // namespace hullpose::skeleton_io
