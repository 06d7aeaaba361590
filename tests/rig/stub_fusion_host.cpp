// The fusion service with the sequence-checking pipeline (seq_check_pipeline.hpp): the fault
// tests use it to prove that no fused frame mixes views of different trigger sequences.
// --seq-period N (first, optional): the nodes replay a looping recording of N frames (soak).
#include <cstring>
#include <string>

#include "hullpose/common/cli.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"
#include "seq_check_pipeline.hpp"

int main(int argc, char** argv) {
  int64_t period = int64_t{1} << hullpose::testing::kPatternBits;
  if (argc > 2 && std::strcmp(argv[1], "--seq-period") == 0) {
    period = hullpose::cli::parse_integer("--seq-period", argv[2]);
    argv[2] = argv[0];
    argv += 2;
    argc -= 2;
  }
  return hullpose::fusion::service_main(
      argc, argv, "rig-stub-fusion-host",
      [period](const hullpose::Rig&, const hullpose::fusion::PipelineOptions&) {
        return std::make_unique<hullpose::testing::SeqCheckPipeline>(period);
      });
}
