// hullpose-fusion-live: the live fusion host (SILHOUETTE + TRIGGER in, SKELETON + STATUS out)
// running carve -> clean-up -> thin -> pose tree + fit. Without fusion_host/pose in the tree,
// frames are published with their real latencies and REASON_FIT_FAILED.
#include "hullpose/fusion_host/fusion_service.hpp"
#include "hullpose/fusion_host/hull_pipeline.hpp"

namespace hullpose::fusion {
#ifdef HULLPOSE_HAVE_POSE
std::unique_ptr<PoseStage> make_pose_stage();  // pose_stage.cpp
#else
std::unique_ptr<PoseStage> make_pose_stage() { return nullptr; }
#endif
}  // namespace hullpose::fusion

int main(int argc, char** argv) {
  using namespace hullpose::fusion;
  return service_main(argc, argv, "hullpose-fusion-live", [](const hullpose::Rig& rig, const PipelineOptions& o) {
    FusionOptions f;
    f.resolution = o.resolution;
    f.tolerance = o.tolerance;
    return std::make_unique<HullPipeline>(rig, f, make_pose_stage(), nullptr);
  });
}
