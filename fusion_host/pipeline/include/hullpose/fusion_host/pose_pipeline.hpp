#pragma once
// The one path from the silhouettes of a trigger instant to its pose and reason, shared by the
// offline replay (fusion_host/replay) and the live service (HullPipeline, fusion_host/service):
//
//   views by camera index -> FusionCore (carve -> clean-up -> thin; fusion_host/core)
//                         -> pose::HullPoseEstimator (bottom-up tree -> fit, hull tracking;
//                         fusion_host/pose)
//                         -> FrameOutcome: valid + the skeleton_t REASON_* to publish
//
// The pose stage sees every frame (an empty skeleton when the hull failed), so that its
// temporal state is the same live and replayed. Construct once per (rig, options); process()
// per frame; the outcome is overwritten by the next call; no allocation per frame at steady
// state. Bad per-frame data never throws (FusionCore counts it).
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <span>

#include "hullpose/common/camera.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/pose/hull_pose_estimator.hpp"

namespace hullpose::fusion {

struct FrameOutcome {
  bool valid = false;
  int8_t reason = 0;  // skeleton_t::REASON_*: the pose stage's, or TOO_FEW_CAMERAS
  // When carving + thinning finished, microseconds after process() began.
  int64_t fused_after_us = -1;
  const FusionResult* hull = nullptr;        // the fusion core's result of this frame
  const pose::PoseEstimate* pose = nullptr;  // the pose stage's result of this frame
};

class PosePipeline {
 public:
  // Throws hullpose::Error on a bad rig or options. `counters`, if given, must outlive this.
  PosePipeline(const Rig& rig, const FusionOptions& fusion, const pose::HullPoseParams& pose,
               Counters* counters);

  // masks[i]: rig.cameras[i]'s silhouette or an empty Mat; rois: optional foreground boxes.
  const FrameOutcome& process(std::span<const cv::Mat> masks, std::span<const PixelRoi> rois = {});

  const FusionCore& core() const { return core_; }
  const pose::HullPoseEstimator& estimator() const { return estimator_; }

 private:
  FusionCore core_;
  pose::HullPoseEstimator estimator_;
  FrameOutcome out_;
};

}  // namespace hullpose::fusion
