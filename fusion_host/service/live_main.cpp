// hullpose-fusion-live: the live fusion host (SILHOUETTE + TRIGGER in, SKELETON + STATUS out)
// running carve -> clean-up -> thin. The pose stage (fusion_host/pose) is not wired in yet:
// frames are published with their real latencies and REASON_FIT_FAILED.
#include "hullpose/fusion_host/fusion_service.hpp"
#include "hullpose/fusion_host/hull_pipeline.hpp"

int main(int argc, char** argv) {
  using namespace hullpose::fusion;
  return service_main(argc, argv, "hullpose-fusion-live", [](const hullpose::Rig& rig, const PipelineOptions& o) {
    FusionOptions f;
    f.resolution = o.resolution;
    f.tolerance = o.tolerance;
    return std::make_unique<HullPipeline>(rig, f, nullptr, nullptr);
  });
}
