// Fuzz target: the camera node's config reader (camera_node/config parse_node_config, which
// load_node_config calls with the file's text) returns a config or throws hullpose::Error, for
// any bytes.
#include <cstdint>

#include "fuzz_file.hpp"
#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/common/check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)hullpose::camera_node::parse_node_config(hullpose::fuzz::text(data, size),
                                                   "/nonexistent/fuzz.node.yaml");
  } catch (const hullpose::Error&) {
  }
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  return {hullpose::fuzz::bytes_of(
              "%YAML:1.0\ncamera_id: 3\nrig_file: rig.yaml\n"
              "source: { type: file, path: \"cam3/seq_%06d.png\", preload: true }\n"
              "bgs: { method: horprasert, learn_frames: 10, params: { epsilon_online: 0.008 } }\n"
              "post: { open_radius: 1, close_radius: 0, min_blob_area: 64, max_hole_area: 64, roi: "
              "[0, 0, 64, 48] }\n"
              "lcm: { url: \"udpm://239.255.76.67:7667?ttl=1\", queue_depth: 8, status_period_ms: "
              "1000 }\n"
              "trigger:\n  edges: wire\n  path: wire.sock\n  connect_timeout_ms: 100\n  "
              "clock_offset_ms: -20\n"),
          hullpose::fuzz::bytes_of(
              "%YAML:1.0\ncamera_id: 0\nrig_file: r.yaml\nsource: { type: synthetic }\n"
              "bgs: { method: sobs }\ntrigger: { edges: gpiod, chip: gpiochip0, line: 17, camera: "
              "free_running }\n")};
}
