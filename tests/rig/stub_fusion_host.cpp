// The fusion service with the sequence-checking pipeline (seq_check_pipeline.hpp): the fault
// tests use it to prove that no fused frame mixes views of different trigger sequences.
// --seq-period N (first, optional): the nodes replay a looping recording of N frames (soak).
#include <cstring>
#include <vector>

#include "hullpose/common/cli.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"
#include "seq_check_pipeline.hpp"

int main(int argc, char** argv) {
  return hullpose::run_tool("rig-stub-fusion-host", argc, argv, [](int c, const char* const* v) {
    int64_t period = int64_t{1} << hullpose::testing::kPatternBits;
    std::vector<const char*> args(v, v + c);
    if (c > 2 && std::strcmp(v[1], "--seq-period") == 0) {
      period = hullpose::cli::parse_integer("--seq-period", v[2]);
      args.erase(args.begin() + 1, args.begin() + 3);
    }
    return hullpose::fusion::service_main(
        static_cast<int>(args.size()), args.data(), "rig-stub-fusion-host",
        [period](const hullpose::Rig&, const hullpose::fusion::PipelineOptions&) {
          return std::make_unique<hullpose::testing::SeqCheckPipeline>(period);
        });
  });
}
