// The fusion service with the sequence-checking pipeline (seq_check_pipeline.hpp): the fault
// tests use it to prove that no fused frame mixes views of different trigger sequences.
#include "hullpose/common/tool.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"
#include "seq_check_pipeline.hpp"

int main(int argc, char** argv) {
  return hullpose::run_tool("rig-stub-fusion-host", argc, argv, [](int c, const char* const* v) {
    return hullpose::fusion::service_main(
        c, v, "rig-stub-fusion-host",
        [](const hullpose::Rig&, const hullpose::fusion::PipelineOptions&) {
          return std::make_unique<hullpose::testing::SeqCheckPipeline>();
        });
  });
}
