#pragma once
// Zero-phase smoothing of the published pose at the cost of one frame of latency: frame n is
// published when frame n + 1 is known, as the weighted mean (w, 1 - 2w, w) of frames n - 1, n,
// n + 1, its bones given back their lengths in frame n. The tracked pose carries a frame-to-frame
// error that a causal filter can only trade for lag (one_euro.hpp); a window centred on the frame
// removes part of it without moving the frame in time, and keeps a pose that moves at constant
// velocity exactly. The issue allows the output one frame of lag (#14); the published skeleton
// keeps its own trigger number and time, so it lags in latency only. Used by the two places that
// publish poses, the live service (fusion_host/service, which also releases a held frame when no
// next one comes) and the replay (fusion_host/replay), so that both publish the same poses.
// Fixed state, no allocation.
#include <array>
#include <string>

#include "hullpose/common/dataset.hpp"
#include "hullpose/common/joints.hpp"

namespace hullpose::pose {

struct LagParams {
  // 1: each frame is published one frame late, smoothed; 0: as soon as it is fitted, as fitted
  // (--lag-frames; the lowest latency, for consumers that want it over accuracy).
  int frames = 1;
  // The neighbours' weight w. 0.25 (the binomial 1-2-1 window) and a box of thirds gave the same
  // figures on make eval's clips (docs/perf-log.md, session 28); the binomial one blurs a
  // fast limb least.
  double weight = 0.25;
  // A frame is smoothed only with neighbours that are valid, consecutive and within this mean
  // joint distance of it (paper 6's pose-jump threshold, as PoseParams::jump_mean_mm): no
  // smoothing across a re-acquisition.
  double jump_mean_mm = 150;
};

// --lag-frames: 0 or 1; throws hullpose::Error naming `what` otherwise.
int parse_lag_frames(const std::string& value, const char* what = "--lag-frames");

class LagSmoother {
 public:
  explicit LagSmoother(LagParams params = {});
  // Frame n as fitted, whether it is published valid, and whether it is the frame right after
  // the last one pushed (consecutive trigger numbers). Returns the pose to publish for the frame
  // held before it (n - 1), or nullptr when none was held (the first frame, or the one after a
  // release()). The pointer is valid until the next call.
  const JointPositions* push(const JointPositions& pose, bool valid, bool follows);
  // The held frame's pose as fitted, for when no next frame is coming (the end of a take, a pause
  // in the triggers); nullptr when none is held. It stays the previous frame of the next push.
  const JointPositions* release();
  bool holding() const { return held_.present; }

 private:
  struct Frame {
    JointPositions pose{};
    bool valid = false;
    bool present = false;
  };
  bool near(const Frame& a, const Frame& b) const;

  LagParams params_;
  // before_: the frame before held_ (present only if it immediately precedes it).
  Frame before_, held_;
  JointPositions out_{};
  std::array<double, kNumBones> lengths_{};
};

}  // namespace hullpose::pose
