#pragma once
// hullpose-calibrate's command line.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hullpose/calibrate/live_provider.hpp"
#include "hullpose/calibrate/rig_calibrator.hpp"

namespace hullpose::calibrate {

struct CommandLine {
  std::filesystem::path images;  // DIR with cam<ID>/<instant>.png ...
  std::vector<std::filesystem::path>
      node_configs;  // ... or live: one camera node config per camera
  LiveOptions live;
  std::filesystem::path out;      // rig file to write
  std::filesystem::path report;   // optional copy of the report
  std::filesystem::path compare;  // optional: another calibration of the rig to compare with
  CalibrationOptions options;
  bool quiet = false;
};

// The options, or nullopt after printing usage() for --help. Throws hullpose::Error naming the
// offending argument (common/cli).
std::optional<CommandLine> parse_command_line(int argc, const char* const* argv);
std::string usage();

}  // namespace hullpose::calibrate
