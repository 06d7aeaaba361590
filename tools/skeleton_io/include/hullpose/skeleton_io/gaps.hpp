#pragma once
// What the exporters do with frames that are not fresh estimates (invalid, or never received).
// A short gap between two fresh poses is filled by linear interpolation of the joint positions:
// over a few frames a limb moves close to a straight line, so the filled pose is near what the
// rig would have seen. A longer gap (or one at either end of the take, with a fresh pose on one
// side only) is left as a gap and flagged: interpolating over it would invent motion. Each
// format then marks what it can (TRC: empty marker fields; C3D: residual -1 for missing, 0 for
// interpolated points; BVH, which has no flag, holds the last pose) and hullpose-export reports
// the flagged frame ranges.
#include <cstdint>
#include <utility>
#include <vector>

#include "hullpose/skeleton_io/take.hpp"

namespace hullpose::skeleton_io {

enum class FrameState : uint8_t { Measured, Filled, Missing };

struct GapReport {
  std::vector<FrameState> state;                    // per frame of the take
  int filled = 0, missing = 0;                      // frames
  std::vector<std::pair<int, int>> missing_ranges;  // [first, last] frame indices, inclusive
};

// Frames of invalid runs of at most `max_fill_frames` between two valid frames get interpolated
// joints (and keep valid = false in the take's own record of them; the report says Filled).
GapReport fill_gaps(std::vector<SkeletonFrame>& frames, int max_fill_frames);

}  // namespace hullpose::skeleton_io
