#pragma once
// The simulated camera: renders this camera's view of the synthetic rig live (synth/: a
// motion drives the avatar in a textured room with soft shadows, slow illumination drift and
// sensor noise). The first `empty_frames` frames show the empty room, for learning the
// background; frame empty_frames + k shows the motion at time k / fps. Frame n gets
// capture_utime = start_utime + n * 1e6 / fps. Triggered (expose()), the background frames are
// still read first (learning), then each trigger shows the motion at time trigger_seq / fps.
//
// Parameters: motion (walk | run | jump | crouch | turn | wave | tpose | FILE.bvh; default walk),
// fps (30), frames (motion frames; 0 = the clip's length, endless for built-in motions),
// empty_frames (30), seed (1), stature_mm (1750), drift (0.08), shadow_strength (0.5),
// flicker (0), noise_sigma (2.0), start_utime (0: the time start() was called; quote it in YAML).
#include <memory>

#include "hullpose/camera_node/frame_source.hpp"

namespace hullpose::camera_node {

class SyntheticSource final : public FrameSource {
 public:
  SyntheticSource(const Params& params, const SourceContext& context);
  ~SyntheticSource() override;
  void start() override;
  GrabStatus grab(Frame& frame, int timeout_ms) override;
  void stop() override;
  std::string describe() const override;
  bool triggerable() const override { return true; }
  void expose(int64_t trigger_seq, int64_t capture_utime) override;

  // The exact silhouette of the last frame grab() returned (CV_8UC1, 255 = person): ground truth.
  const cv::Mat& truth() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace hullpose::camera_node
