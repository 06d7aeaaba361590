#include "hullpose/skeleton_io/humanoid.hpp"

#include "hullpose/common/check.hpp"

namespace hullpose::skeleton_io {
namespace {

// Unity bone, the BvhSkeleton node it follows, its humanoid parent. The shoulders (clavicles)
// are the zero-length nodes between the chest and the shoulder joints.
struct Spec {
  std::string_view unity, node, parent;
};
constexpr std::array<Spec, kNumHumanoidBones> kSpecs = {{
    {"Hips", "LBack", ""},
    {"Spine", "Back", "Hips"},
    {"Chest", "UBack", "Spine"},
    {"UpperChest", "Chest", "Chest"},
    {"Neck", "Neck", "UpperChest"},
    {"Head", "Head", "Neck"},
    {"LeftShoulder", "Chest_LSho", "UpperChest"},
    {"LeftUpperArm", "LSho", "LeftShoulder"},
    {"LeftLowerArm", "LElb", "LeftUpperArm"},
    {"LeftHand", "LHand", "LeftLowerArm"},
    {"RightShoulder", "Chest_RSho", "UpperChest"},
    {"RightUpperArm", "RSho", "RightShoulder"},
    {"RightLowerArm", "RElb", "RightUpperArm"},
    {"RightHand", "RHand", "RightLowerArm"},
    {"LeftUpperLeg", "LHip", "Hips"},
    {"LeftLowerLeg", "LKne", "LeftUpperLeg"},
    {"LeftFoot", "LAnk", "LeftLowerLeg"},
    {"RightUpperLeg", "RHip", "Hips"},
    {"RightLowerLeg", "RKne", "RightUpperLeg"},
}};

// BVH frame (right-handed, Y up, left on +X) to Unity's (left-handed, Y up, left on -X): mirror x.
Eigen::Vector3d to_unity(const Eigen::Vector3d& v) {
  return {-v.x(), v.y(), v.z()};
}
Eigen::Quaterniond to_unity(const Eigen::Quaterniond& q) {
  return {q.w(), q.x(), -q.y(), -q.z()};
}

}  // namespace

HumanoidMap::HumanoidMap(const BvhSkeleton& skeleton) : skeleton_(skeleton) {
  for (size_t i = 0; i < kSpecs.size(); ++i) {
    Entry& e = entries_[i];
    e.name = kSpecs[i].unity;
    e.node = skeleton.find(std::string(kSpecs[i].node));
    HULLPOSE_ASSERT(e.node >= 0);
    e.parent = -1;
    for (size_t k = 0; k < i; ++k)
      if (kSpecs[k].unity == kSpecs[i].parent) e.parent = static_cast<int>(k);
    HULLPOSE_ASSERT(i == 0 || e.parent >= 0);
  }
}

void HumanoidMap::pose(const JointPositions& joints_mm,
                       std::array<HumanoidBone, kNumHumanoidBones>& out) const {
  thread_local std::vector<Eigen::Quaterniond> global;
  skeleton_.solve_rotations(joints_mm, global);
  const auto& nodes = skeleton_.nodes();
  const auto origin = [&](int node) -> Eigen::Vector3d {
    return BvhSkeleton::to_bvh(
               joints_mm[static_cast<size_t>(nodes[static_cast<size_t>(node)].joint)]) /
           100.0;  // m
  };
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    const Eigen::Quaterniond& g = global[static_cast<size_t>(e.node)];
    HumanoidBone& b = out[i];
    b.name = e.name;
    if (e.parent < 0) {
      b.position = to_unity(origin(e.node));
      b.rotation = to_unity(g);
      continue;
    }
    const int parent_node = entries_[static_cast<size_t>(e.parent)].node;
    const Eigen::Quaterniond& gp = global[static_cast<size_t>(parent_node)];
    b.position = to_unity(gp.conjugate() * (origin(e.node) - origin(parent_node)));
    b.rotation = to_unity(gp.conjugate() * g).normalized();
  }
}

}  // namespace hullpose::skeleton_io
