// The fusion service with the sequence-checking stand-in pipeline (seq_check_pipeline.hpp), for
// the system tests of the rig's plumbing until the real pipeline is wired in.
#include "hullpose/fusion_host/fusion_service.hpp"
#include "seq_check_pipeline.hpp"

int main(int argc, char** argv) {
  return hullpose::fusion::service_main(argc, argv, "rig-stub-fusion-host", [](const hullpose::Rig&, const hullpose::fusion::PipelineOptions&) {
    return std::make_unique<hullpose::testing::SeqCheckPipeline>();
  });
}
