// hullpose-fusion-host: the live LCM service (SILHOUETTE + TRIGGER in, SKELETON + STATUS out;
// fusion_host/service) by default; `--replay DIR --out FILE` runs the same frame -> pose path
// offline over a dataset instead (fusion_host/replay).
#include "hullpose/common/tool.hpp"
#include "hullpose/fusion_host/hull_pipeline.hpp"
#include "hullpose/replay/replay.hpp"

namespace {
int run(int argc, const char* const* argv) {
  using namespace hullpose;
  if (replay::is_replay_command(argc, argv)) return replay::replay_cli(argc, argv);
  return fusion::service_main(argc, argv, "hullpose-fusion-host", fusion::make_live_pipeline);
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-fusion-host", argc, argv, run);
}
