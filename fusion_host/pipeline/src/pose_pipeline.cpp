#include "hullpose/fusion_host/pose_pipeline.hpp"

#include <hullpose_msg/skeleton_t.hpp>

#include "hullpose/common/time.hpp"

namespace hullpose::fusion {

PosePipeline::PosePipeline(const Rig& rig, const FusionOptions& fusion,
                           const pose::PoseParams& pose, Counters* counters)
    : core_(rig, fusion, counters), estimator_(pose) {}

const FrameOutcome& PosePipeline::process(std::span<const cv::Mat> masks,
                                          std::span<const PixelRoi> rois) {
  const StageTimer timer;
  const FusionResult& hull = core_.process(masks, rois);
  out_.fused_after_us = timer.elapsed_us();
  const pose::PoseEstimate& pose =
      estimator_.estimate(hull.valid ? std::span<const Eigen::Vector3i>(hull.skeleton_voxels)
                                     : std::span<const Eigen::Vector3i>(),
                          hull.grid);
  out_.hull = &hull;
  out_.pose = &pose;
  out_.valid = pose.valid;
  out_.reason = pose.reason;
  // The pose stage sees an empty skeleton either way; the reason names the cause.
  if (!hull.valid && hull.failure == FusionFailure::kTooFewViews) {
    out_.valid = false;
    out_.reason = hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS;
  }
  return out_;
}

}  // namespace hullpose::fusion
