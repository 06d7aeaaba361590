#pragma once
// One skeleton as the consumers see it (the web view, the exporters, the streaming bridges), and
// a recorded take: the frames of an estimate CSV (docs/conventions.md) or of the SKELETON channel
// of an lcm-logger log. Consumers read skeletons through this type only, so a new source (a new
// file format, a new wire type) is one function here.
#include <array>
#include <cstdint>
#include <filesystem>
#include <hullpose_msg/skeleton_t.hpp>
#include <string>
#include <vector>

#include "hullpose/common/dataset.hpp"
#include "hullpose/common/joints.hpp"

namespace hullpose::skeleton_io {

// Eigen leaves vectors uninitialised: frames start with every joint at the origin.
inline JointPositions zero_joints() {
  JointPositions j;
  j.fill(Eigen::Vector3d::Zero());
  return j;
}

struct SkeletonFrame {
  int64_t utime = 0;   // trigger instant (0 when the source has no clock: estimate CSV)
  int64_t seq = 0;     // trigger sequence (the frame number of an estimate CSV)
  bool valid = false;  // a fresh estimate of this instant (skeleton_t.valid)
  int reason = 0;      // skeleton_t REASON_*
  JointPositions joints = zero_joints();  // mm, rig frame (z up)
  std::array<float, kNumJoints> confidence{};
  int64_t cameras_used_mask = 0;
  int num_cameras_used = 0;
  int32_t published_us = 0;  // trigger -> published (0 unknown)
  // skeleton_t.model_version / the estimate CSV's `model`: 0 = provisional (the fusion host's
  // body model still converging, bone lengths may change); n >= 1 = held body model n, whose bone
  // lengths every frame with that n has exactly.
  int32_t model_version = 0;
};

// False (frame untouched) unless the message carries the 25 joints of common/joints.hpp, finite,
// and a model_version >= 0.
bool from_message(const hullpose_msg::skeleton_t& msg, SkeletonFrame& out);
void to_message(const SkeletonFrame& frame, const std::string& rig_id,
                hullpose_msg::skeleton_t& out);

struct Take {
  double fps = 30;
  // One entry per trigger instant from the first to the last seen: sequences the source skipped
  // are inserted as invalid frames (reason REASON_TOO_FEW_CAMERAS), so frame i is at i / fps.
  std::vector<SkeletonFrame> frames;
  int64_t malformed = 0;  // log events on the channel that failed the wire check or decoding
  int64_t inserted = 0;   // missing sequences filled in as invalid frames
};

// Reads an estimate CSV or an lcm-logger log (told apart by the log's sync word). `fps` is used
// for the CSV (which has no clock) and for a log whose times do not give a rate; a log takes
// its rate from the median utime step. Throws hullpose::Error naming the file on bad content.
Take read_take(const std::filesystem::path& path, double fps = 30,
               const std::string& channel = "SKELETON");

}  // namespace hullpose::skeleton_io
