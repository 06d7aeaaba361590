// hullpose-fusion-host: `--replay DIR --out FILE` runs the offline pipeline over a dataset; the
// live LCM service mode is the default (added with the fusion host service).
#include <iostream>
#include <string_view>
#include <vector>

#include "hullpose/common/check.hpp"
#include "hullpose/replay/replay.hpp"

int main(int argc, char** argv) {
  const std::vector<std::string_view> args(argv + 1, argv + argc);
  try {
    if (hullpose::replay::is_replay_command(args)) return hullpose::replay::replay_cli(args);
    std::cerr << "hullpose-fusion-host: error: only --replay DIR --out FILE is available in this build\n";
    return 2;
  } catch (const hullpose::Error& e) {
    std::cerr << "hullpose-fusion-host: error: " << e.what() << "\n";
    return 2;
  }
}
