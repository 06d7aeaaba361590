#pragma once
// BVH motion-capture files: parsing and forward kinematics, in the file's own units and axes.
// Mapping onto the 25-joint model, units and the rig frame is motion.hpp's job.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hullpose::synth {

enum class BvhChannel { Xposition, Yposition, Zposition, Xrotation, Yrotation, Zrotation };

struct BvhJoint {
  std::string name;  // End Sites are named "<parent>_End"
  int parent = -1;   // parents precede children
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<BvhChannel> channels;
  int first_channel = 0;  // column of channels[0] in a motion line
  int line = 0;           // where the joint is declared, for error messages
};

struct BvhClip {
  std::string source;  // file name, for messages
  std::vector<BvhJoint> joints;
  int channel_count = 0;
  int frames = 0;
  double frame_time_s = 0;
  std::vector<double> motion;  // frames x channel_count, row-major

  // Index of the joint with this name, or -1.
  int find(std::string_view name) const;
  // Global rotation and position of every joint (End Sites included) at `frame`, in file units
  // and axes. The outputs are resized to joints.size(). frame = -1 gives the rest pose.
  void forward_kinematics(int frame, std::vector<Eigen::Matrix3d>& rotation,
                          std::vector<Eigen::Vector3d>& position) const;
};

// Throws hullpose::Error naming the file and line (or joint) on any problem: unknown channel,
// malformed hierarchy, non-finite or missing numbers, a motion section shorter than its header.
BvhClip parse_bvh(std::string_view text, const std::string& source);
BvhClip load_bvh(const std::filesystem::path& path);

}  // namespace hullpose::synth
