#pragma once
// The fusion host's real pipeline behind the FramePipeline seam: the assembled views -> carve ->
// clean-up -> thin (FusionCore, fusion_host/core) -> pose tree + model fit (a PoseStage; the
// pose stage of fusion_host/pose by default). Frame for frame it does what the offline replay
// (fusion_host/replay) does, so live and replayed estimates agree.
#include <Eigen/Core>
#include <memory>
#include <span>
#include <vector>

#include "hullpose/common/counters.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/fusion_host/frame_pipeline.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"

namespace hullpose::fusion {

class PoseStage {
 public:
  virtual ~PoseStage() = default;
  // One frame's fusion result in (hull and curve skeleton; invalid when the hull failed), the
  // pose out (valid, reason, joints, confidence).
  virtual void estimate(const FusionResult& fused, PoseEstimate& out) = 0;
};

class HullPipeline final : public FramePipeline {
 public:
  // pose == nullptr: hull and curve skeleton only; every frame that carves is published with
  // REASON_FIT_FAILED and its real latencies (for measuring the fusion stages alone).
  HullPipeline(const Rig& rig, const FusionOptions& options, std::unique_ptr<PoseStage> pose,
               Counters* counters);
  void process(const AssembledFrame& frame, PoseEstimate& out) override;
  const FusionResult& last_fusion() const { return *last_; }

 private:
  const Rig& rig_;
  FusionCore core_;
  std::unique_ptr<PoseStage> pose_;
  std::vector<cv::Mat> masks_;
  std::vector<PixelRoi> rois_;
  const FusionResult* last_ = nullptr;
};

// The fusion host's live pipeline: HullPipeline with the pose stage of fusion_host/pose.
std::unique_ptr<FramePipeline> make_live_pipeline(const Rig& rig, const PipelineOptions& options);

}  // namespace hullpose::fusion
