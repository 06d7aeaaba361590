#include "hullpose/fusion_host/hull_pipeline.hpp"

#include <hullpose_msg/skeleton_t.hpp>

#include "hullpose/common/time.hpp"

namespace hullpose::fusion {

HullPipeline::HullPipeline(const Rig& rig, const FusionOptions& options, std::unique_ptr<PoseStage> pose, Counters* counters)
    : rig_(rig), core_(rig, options, counters), pose_(std::move(pose)) {
  masks_.reserve(rig.cameras.size());
  rois_.reserve(rig.cameras.size());
}

void HullPipeline::process(const AssembledFrame& frame, PoseEstimate& out) {
  views_by_camera_index(frame, rig_.cameras.size(), masks_, rois_);
  const FusionResult& r = core_.process(masks_, rois_);
  last_ = &r;
  out.fused_utime = realtime_utime();
  if (!r.valid) {
    out.valid = false;
    out.reason = r.failure == FusionFailure::kTooFewViews ? hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS
                                                          : hullpose_msg::skeleton_t::REASON_EMPTY_HULL;
    return;
  }
  if (!pose_) {
    out.valid = false;
    out.reason = hullpose_msg::skeleton_t::REASON_FIT_FAILED;
    return;
  }
  pose_->estimate(r.skeleton_voxels, r.grid, out);
}

}  // namespace hullpose::fusion
