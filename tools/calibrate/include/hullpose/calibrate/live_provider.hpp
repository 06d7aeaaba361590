#pragma once
// Calibration views from live cameras: each camera's frame source (camera_node/source), chosen
// by name (libcamera, v4l2, file, synthetic) and configured exactly as in that camera node's
// config file. Instant k holds frame k * stride of every camera: with the hardware trigger the
// cameras' frame counters advance together, so those frames show the board at the same moment.
// Live feedback per image (board found, views kept, coverage, view error, outliers) comes from
// RigCalibrator as the instants arrive.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hullpose/calibrate/view_provider.hpp"
#include "hullpose/camera_node/frame_source.hpp"
#include "hullpose/camera_node/params.hpp"

namespace hullpose::calibrate {

struct LiveCamera {
  int camera_id = 0;
  std::string source_type;  // a name in the source registry
  camera_node::Params params;
  camera_node::SourceContext context;  // context.camera gives the image size
};

// A camera node's config file: its camera id and source; the image size from the rig file it
// names (a nominal rig before the first calibration). Throws naming the file and what is wrong.
LiveCamera live_camera_from_node_config(const std::filesystem::path& node_config);

struct LiveOptions {
  int max_instants = 0;  // 0: until a source ends
  int stride = 1;        // frames per instant: the others are skipped (moving the board takes time)
  int timeout_ms = 2000;  // a camera that delivers no frame this long is an error, naming it
};

class LiveViewProvider final : public ViewProvider {
 public:
  // Creates and starts every camera's source. Throws hullpose::Error naming the camera (and,
  // from the backend, the device and what was tried) when one is absent or misconfigured.
  LiveViewProvider(
      std::vector<LiveCamera> cameras, LiveOptions options,
      const camera_node::SourceRegistry& registry = camera_node::SourceRegistry::builtin());
  ~LiveViewProvider() override;  // stops the sources
  LiveViewProvider(const LiveViewProvider&) = delete;
  LiveViewProvider& operator=(const LiveViewProvider&) = delete;

  // Instants are named live00000, live00001, ... (pick the floor view by that name). False once
  // any source ends or max_instants were delivered.
  bool next(CaptureInstant& out) override;
  std::string describe() const override;

 private:
  struct Camera {
    int id = 0;
    std::unique_ptr<camera_node::FrameSource> source;
  };
  std::vector<Camera> cameras_;
  LiveOptions options_;
  int delivered_ = 0;
  camera_node::Frame frame_;
};

}  // namespace hullpose::calibrate
