#pragma once
// The subject as a BVH skeleton: a hierarchy with the subject's bone lengths in a T-pose rest
// (so Blender or a game engine can retarget it) and, per pose, the root position and one local
// rotation per joint that reproduce our 25 joints by forward kinematics.
//
// Frame and units: BVH convention, Y up, centimetres; rig (x, y, z) mm -> BVH (x, z, -y) / 10.
// The rest pose faces +Z with the subject's left on +X. Root (LBack, the pelvis): channels
// Xposition Yposition Zposition Zrotation Xrotation Yrotation; every other joint Zrotation
// Xrotation Yrotation (local R = Rz * Rx * Ry, as BVH readers compose them).
//
// Rotations: a joint with one child turns by the smallest rotation, relative to its parent's
// frame, that points the child's rest offset along the observed bone (our model observes no
// twist). The pelvis and the chest have three children each; their rotation is the best fit
// (Kabsch) of the three rest offsets to the observed ones, and each child hangs from a zero-length
// joint of its own ("Chest_LSho": the clavicle) that takes up what the rigid fit leaves, so
// every joint is reproduced exactly (to rounding) when the bone lengths are the subject's.
#include <Eigen/Geometry>
#include <array>
#include <ostream>
#include <string>
#include <vector>

#include "hullpose/skeleton_io/take.hpp"

namespace hullpose::skeleton_io {

using BoneLengths = std::array<double, kNumBones>;  // mm, in the order of kBones

// The subject's bone lengths for a take's one BVH hierarchy: when some valid frames come from a
// held body model (model_version >= 1), the lengths of the newest model's frames — which every
// such frame has exactly, so the BVH reproduces them to float rounding; otherwise the median
// length of each bone over the valid frames. 0 valid frames: Error.
BoneLengths subject_bone_lengths(const std::vector<SkeletonFrame>& frames);
// The model_version subject_bone_lengths takes the lengths from (0: the median of all).
int32_t held_model_version(const std::vector<SkeletonFrame>& frames);
BoneLengths bone_lengths(const JointPositions& joints);

class BvhSkeleton {
 public:
  struct Node {
    std::string name;
    int parent = -1;  // index into nodes(), -1 for the root
    int joint = -1;   // the hullpose joint at this node's origin
    int child_joint =
        -1;  // the single hullpose joint this node's rotation aims at (-1: Kabsch node)
    Eigen::Vector3d offset;  // from the parent's origin, parent's rest frame, cm
    bool end_site = false;   // "End Site": no channels
  };

  explicit BvhSkeleton(const BoneLengths& lengths_mm);

  const std::vector<Node>& nodes() const { return nodes_; }
  int num_channels() const { return num_channels_; }
  // Index of the node named `name`, or -1.
  int find(const std::string& name) const;

  // "HIERARCHY ... MOTION\nFrames: N\nFrame Time: T\n"
  void write_header(std::ostream& out, int frames, double frame_time_s) const;
  void write_hierarchy(std::ostream& out) const;

  // Global rotations (BVH frame) of every node for one pose; end sites get their parent's.
  void solve_rotations(const JointPositions& joints_mm,
                       std::vector<Eigen::Quaterniond>& global) const;
  // The motion channels of one pose: root position (cm) and ZXY Euler angles (degrees) per node.
  // Angles are unwrapped towards `channels`' previous content when it has num_channels() values,
  // so curves stay continuous from frame to frame.
  void solve(const JointPositions& joints_mm, std::vector<double>& channels) const;
  // Forward kinematics of channel values (what a BVH reader computes): node origins in rig mm.
  void forward(const std::vector<double>& channels,
               std::vector<Eigen::Vector3d>& positions_mm) const;

  // One motion line ("v v v ...\n", fixed precision, no allocation once `line` has grown).
  static void format_line(const std::vector<double>& channels, std::string& line);

  static Eigen::Vector3d to_bvh(const Eigen::Vector3d& rig_mm);    // cm, Y up
  static Eigen::Vector3d from_bvh(const Eigen::Vector3d& bvh_cm);  // mm, z up

 private:
  int add(std::string name, int parent, int joint, int child_joint, const Eigen::Vector3d& offset,
          bool end_site);
  void write_node(std::ostream& out, int node, int depth) const;

  std::vector<Node> nodes_;
  std::vector<std::vector<int>> children_;
  int num_channels_ = 0;
};

}  // namespace hullpose::skeleton_io
