#pragma once
// The fusion host's real pipeline behind the service's FramePipeline seam: the assembled views
// laid out by camera index, then the PosePipeline (fusion_host/pipeline) that the offline replay
// runs too, so live and replayed estimates agree frame for frame.
#include <memory>
#include <vector>

#include "hullpose/fusion_host/frame_pipeline.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"
#include "hullpose/fusion_host/pose_pipeline.hpp"

namespace hullpose::fusion {

class HullPipeline final : public FramePipeline {
 public:
  HullPipeline(const Rig& rig, const FusionOptions& fusion, const pose::PoseParams& pose,
               Counters* counters);
  void process(const AssembledFrame& frame, PoseEstimate& out) override;
  const PosePipeline& pipeline() const { return pipeline_; }

 private:
  const Rig& rig_;
  PosePipeline pipeline_;
  std::vector<cv::Mat> masks_;
  std::vector<PixelRoi> rois_;
};

// The fusion host's live pipeline: HullPipeline with the default pose parameters.
std::unique_ptr<FramePipeline> make_live_pipeline(const Rig& rig, const PipelineOptions& options);

}  // namespace hullpose::fusion
