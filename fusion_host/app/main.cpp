// hullpose-fusion-host: the live LCM service (SILHOUETTE + TRIGGER in, SKELETON + STATUS out;
// fusion_host/service) by default; `--replay DIR --out FILE` runs the offline pipeline over a
// dataset instead.
#include <iostream>

#include "hullpose/common/check.hpp"
#include "hullpose/fusion_host/hull_pipeline.hpp"
#include "hullpose/replay/replay.hpp"

int main(int argc, char** argv) {
  try {
    if (hullpose::replay::is_replay_command(argc, argv)) return hullpose::replay::replay_cli(argc, argv);
  } catch (const hullpose::Error& e) {
    std::cerr << "hullpose-fusion-host: error: " << e.what() << "\n";
    return 2;
  }
  return hullpose::fusion::service_main(argc, argv, "hullpose-fusion-host", hullpose::fusion::make_live_pipeline);
}
