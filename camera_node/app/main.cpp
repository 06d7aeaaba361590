// hullpose-camera-node --config FILE: one camera's capture -> silhouette -> LCM process.
#include <string>

#include "hullpose/camera_node/camera_node.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/tool.hpp"

namespace {
int run(int argc, const char* const* argv) {
  using namespace hullpose;
  std::string config;
  cli::CommandLine line(
      "usage: hullpose-camera-node --config FILE\n"
      "  One camera of the rig: capture, background subtraction, silhouette on LCM (SILHOUETTE).\n"
      "  The file's trigger: section wires the hardware trigger input (edges: gpiod, chip, line;\n"
      "  or edges: wire, path for a simulated rig) so every silhouette carries the trigger\n"
      "  sequence of the master (camera_node/config/.../node_config.hpp documents every field).\n");
  line.option("--config", config);
  if (!line.parse(argc, argv)) return 0;
  HULLPOSE_THROW_UNLESS(!config.empty(), "missing --config FILE (see --help)");
  const camera_node::NodeConfig node_config = camera_node::load_node_config(config);
  const std::unique_ptr<bus::Bus> bus = camera_node::open_node_bus(node_config);
  camera_node::CameraNode node(node_config, *bus);
  hullpose::catch_stop_signals();
  node.start();
  node.run(stop_flag());
  node.stop();
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-camera-node", argc, argv, run);
}
