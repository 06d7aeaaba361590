#include "hullpose/fusion_host/hull_pipeline.hpp"

#include <hullpose_msg/skeleton_t.hpp>

#include "hullpose/common/time.hpp"
#include "hullpose/pose/hull_pose_estimator.hpp"

namespace hullpose::fusion {

HullPipeline::HullPipeline(const Rig& rig, const FusionOptions& options,
                           std::unique_ptr<PoseStage> pose, Counters* counters)
    : rig_(rig), core_(rig, options, counters), pose_(std::move(pose)) {
  masks_.reserve(rig.cameras.size());
  rois_.reserve(rig.cameras.size());
}

void HullPipeline::process(const AssembledFrame& frame, PoseEstimate& out) {
  views_by_camera_index(frame, rig_.cameras.size(), masks_, rois_);
  const FusionResult& r = core_.process(masks_, rois_);
  last_ = &r;
  out.fused_utime = realtime_utime();
  if (!pose_) {
    out.valid = false;
    out.reason = r.valid ? hullpose_msg::skeleton_t::REASON_FIT_FAILED
                         : hullpose_msg::skeleton_t::REASON_EMPTY_HULL;
  } else {
    // As the offline replay does: the pose stage sees every frame (an empty skeleton when the
    // hull failed), so its temporal state and the reused pose match the replay's.
    pose_->estimate(r, out);
  }
  if (!r.valid && r.failure == FusionFailure::kTooFewViews) {
    out.valid = false;
    out.reason = hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS;
  }
}

namespace {

class PoseEstimatorStage final : public PoseStage {
 public:
  explicit PoseEstimatorStage(const pose::HullPoseParams& params) : estimator_(params) {}
  void estimate(const FusionResult& fused, PoseEstimate& out) override {
    const pose::PoseEstimate& p =
        fused.valid ? estimator_.estimate(fused.skeleton_voxels, &fused.hull, fused.grid)
                    : estimator_.estimate({}, nullptr, fused.grid);
    out.valid = p.valid;
    out.reason = p.reason;
    if (!p.has_pose) return;  // nothing to show yet: zeros, confidence 0
    for (size_t j = 0; j < p.joints_mm.size(); ++j) {
      out.position_mm[j] = {static_cast<float>(p.joints_mm[j].x()),
                            static_cast<float>(p.joints_mm[j].y()),
                            static_cast<float>(p.joints_mm[j].z())};
      out.confidence[j] = p.confidence[j];
    }
  }

 private:
  pose::HullPoseEstimator estimator_;
};

}  // namespace

std::unique_ptr<FramePipeline> make_live_pipeline(const Rig& rig, const PipelineOptions& options) {
  FusionOptions f;
  f.resolution = options.resolution;
  f.tolerance = options.tolerance;
  f.backend = gpu::parse_backend(options.backend);
  pose::HullPoseParams p;
  p.mode = pose::parse_pose_mode(options.pose);
  return std::make_unique<HullPipeline>(rig, f, std::make_unique<PoseEstimatorStage>(p), nullptr);
}

}  // namespace hullpose::fusion
