// The pose stage of fusion_host/pose (tree + model fit) behind HullPipeline's PoseStage seam.
// Built into hullpose-fusion-live when fusion_host/pose is in the tree.
#include "hullpose/fusion_host/hull_pipeline.hpp"
#include "hullpose/pose/pose_estimator.hpp"

namespace hullpose::fusion {
namespace {

class PoseEstimatorStage final : public PoseStage {
 public:
  void estimate(std::span<const Eigen::Vector3i> skeleton, const VoxelGridSpec& grid, PoseEstimate& out) override {
    const pose::PoseEstimate& p = estimator_.estimate(skeleton, grid);
    out.valid = p.valid;
    out.reason = p.reason;
    if (!p.has_pose) return;  // nothing to show yet: zeros, confidence 0
    for (size_t j = 0; j < p.joints_mm.size(); ++j) {
      out.position_mm[j] = {static_cast<float>(p.joints_mm[j].x()), static_cast<float>(p.joints_mm[j].y()),
                            static_cast<float>(p.joints_mm[j].z())};
      out.confidence[j] = p.confidence[j];
    }
  }

 private:
  pose::PoseEstimator estimator_;
};

}  // namespace

std::unique_ptr<PoseStage> make_pose_stage() { return std::make_unique<PoseEstimatorStage>(); }

}  // namespace hullpose::fusion
