// hullpose-camera-node --config FILE: one camera's capture -> silhouette -> LCM process.
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>

#include "hullpose/camera_node/camera_node.hpp"
#include "hullpose/common/check.hpp"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }
}  // namespace

int main(int argc, char** argv) {
  using namespace hullpose;
  std::string config;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--config") == 0 && i + 1 < argc) {
      config = argv[++i];
    } else if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::printf(
          "usage: hullpose-camera-node --config FILE\n"
          "  One camera of the rig: capture, background subtraction, silhouette on LCM (SILHOUETTE).\n"
          "  The file's trigger: section wires the hardware trigger input (edges: gpiod, chip, line;\n"
          "  or edges: wire, path for a simulated rig) so every silhouette carries the trigger\n"
          "  sequence of the master (camera_node/config/.../node_config.hpp documents every field).\n");
      return 0;
    } else {
      std::fprintf(stderr, "hullpose-camera-node: error: unknown argument '%s' (usage: --config FILE)\n", argv[i]);
      return 2;
    }
  }
  if (config.empty()) {
    std::fprintf(stderr, "hullpose-camera-node: error: missing --config FILE\n");
    return 2;
  }
  try {
    camera_node::CameraNode node(camera_node::load_node_config(config));
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    node.start();
    node.run(g_stop);
    node.stop();
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "hullpose-camera-node: error: %s\n", e.what());
    return 2;
  }
}
