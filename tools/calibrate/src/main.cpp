// hullpose-calibrate: checkerboard calibration of the whole rig, written as the rig file.
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "hullpose/calibrate/options.hpp"
#include "hullpose/calibrate/rig_calibrator.hpp"
#include "hullpose/calibrate/rig_compare.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/tool.hpp"

namespace {

int run(int argc, const char* const* argv) {
  using namespace hullpose::calibrate;
  const std::optional<CommandLine> parsed = parse_command_line(argc, argv);
  if (!parsed) return 0;
  const CommandLine& cli = *parsed;
  std::unique_ptr<ViewProvider> views;
  if (cli.node_configs.empty()) {
    views = std::make_unique<FolderViewProvider>(cli.images);
  } else {
    std::vector<LiveCamera> cameras;
    for (const auto& file : cli.node_configs) cameras.push_back(live_camera_from_node_config(file));
    views = std::make_unique<LiveViewProvider>(std::move(cameras), cli.live);
  }
  std::cout << "calibrating from " << views->describe() << "\n";
  RigCalibrator calibrator(cli.options, cli.quiet ? nullptr : &std::cout);
  calibrator.add_all(*views);
  const CalibrationResult result = calibrator.solve();
  hullpose::save_rig(result.rig, cli.out);
  print_report(std::cout, result);
  if (!cli.compare.empty())
    print_difference(std::cout, compare_rigs(result.rig, hullpose::load_rig(cli.compare)));
  if (!cli.report.empty()) {
    std::ofstream report(cli.report);
    HULLPOSE_THROW_UNLESS(report, cli.report.string() << ": cannot write the report");
    print_report(report, result);
  }
  std::cout << "wrote " << cli.out.string() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-calibrate", argc, argv, run);
}
