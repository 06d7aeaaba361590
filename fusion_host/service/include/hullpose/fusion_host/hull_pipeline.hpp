#pragma once
// The fusion host's real pipeline behind the FramePipeline seam: the assembled views -> carve ->
// clean-up -> thin (FusionCore, fusion_host/core) -> pose tree + model fit (a PoseStage: the
// pose stage of fusion_host/pose plugs in here).
#include <Eigen/Core>
#include <memory>
#include <span>
#include <vector>

#include "hullpose/common/counters.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/fusion_host/frame_pipeline.hpp"

namespace hullpose::fusion {

class PoseStage {
 public:
  virtual ~PoseStage() = default;
  // Curve-skeleton voxels of one frame in, the pose out (valid, reason, joints, confidence).
  virtual void estimate(std::span<const Eigen::Vector3i> skeleton, const VoxelGridSpec& grid, PoseEstimate& out) = 0;
};

class HullPipeline final : public FramePipeline {
 public:
  // pose == nullptr: hull and curve skeleton only; every frame that carves is published with
  // REASON_FIT_FAILED (no pose stage built), with its real latencies.
  HullPipeline(const Rig& rig, const FusionOptions& options, std::unique_ptr<PoseStage> pose, Counters* counters);
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

}  // namespace hullpose::fusion
