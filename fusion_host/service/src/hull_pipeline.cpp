#include "hullpose/fusion_host/hull_pipeline.hpp"

namespace hullpose::fusion {

HullPipeline::HullPipeline(const Rig& rig, const FusionOptions& fusion,
                           const pose::HullPoseParams& pose, Counters* counters)
    : rig_(rig), pipeline_(rig, fusion, pose, counters) {
  masks_.reserve(rig.cameras.size());
  rois_.reserve(rig.cameras.size());
}

void HullPipeline::process(const AssembledFrame& frame, PoseEstimate& out) {
  views_by_camera_index(frame, rig_.cameras.size(), masks_, rois_);
  const FrameOutcome& r = pipeline_.process(masks_, rois_);
  out.fused_after_us = r.fused_after_us;
  out.valid = r.valid;
  out.reason = r.reason;
  if (r.hull && r.hull->valid) {
    out.hull = &r.hull->hull;
    out.hull_grid = &r.hull->grid;
  }
  if (!r.pose->has_pose) return;  // nothing to show yet: zeros, confidence 0
  out.model_version = r.pose->model_version;
  for (size_t j = 0; j < r.pose->joints_mm.size(); ++j) {
    const Eigen::Vector3d& p = r.pose->joints_mm[j];
    out.position_mm[j] = {static_cast<float>(p.x()), static_cast<float>(p.y()),
                          static_cast<float>(p.z())};
    out.confidence[j] = r.pose->confidence[j];
  }
}

std::unique_ptr<FramePipeline> make_live_pipeline(const Rig& rig, const PipelineOptions& options) {
  FusionOptions f;
  f.resolution = options.resolution;
  f.tolerance = options.tolerance;
  f.backend = gpu::parse_backend(options.backend);
  pose::HullPoseParams p;
  p.mode = pose::parse_pose_mode(options.pose);
  p.filter.min_cutoff_hz = options.smooth_hz;
  return std::make_unique<HullPipeline>(rig, f, p, nullptr);
}

}  // namespace hullpose::fusion
