#include "hullpose/calibrate/live_provider.hpp"

#include <cstdio>

#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::calibrate {

LiveCamera live_camera_from_node_config(const std::filesystem::path& node_config) {
  const camera_node::NodeConfig config = camera_node::load_node_config(node_config);
  HULLPOSE_THROW_UNLESS(std::filesystem::is_regular_file(config.rig_file),
                        node_config.string()
                            << ": rig_file " << config.rig_file.string()
                            << " not found; live calibration takes camera " << config.camera_id
                            << "'s image size from it (a nominal rig will do)");
  const Rig rig = load_rig(config.rig_file);
  const CameraModel* camera = rig.find(config.camera_id);
  HULLPOSE_THROW_UNLESS(camera != nullptr, node_config.string() << ": camera " << config.camera_id
                                                                << " is not in rig file "
                                                                << config.rig_file.string());
  LiveCamera live;
  live.camera_id = config.camera_id;
  live.source_type = config.source.type;
  live.params = config.source.params;
  live.context.camera_id = config.camera_id;
  live.context.camera = *camera;
  live.context.volume = rig.volume;
  live.context.base_dir = config.base_dir;
  return live;
}

LiveViewProvider::LiveViewProvider(std::vector<LiveCamera> cameras, LiveOptions options,
                                   const camera_node::SourceRegistry& registry)
    : options_(options) {
  HULLPOSE_THROW_UNLESS(!cameras.empty(), "live calibration: no cameras given");
  HULLPOSE_THROW_UNLESS(
      options_.stride >= 1 && options_.max_instants >= 0 && options_.timeout_ms > 0,
      "live calibration: stride must be >= 1, max instants >= 0 and the timeout > 0");
  for (auto& c : cameras) {
    for (const auto& other : cameras_)
      HULLPOSE_THROW_UNLESS(other.id != c.camera_id,
                            "live calibration: camera " << c.camera_id << " given twice");
    Camera camera;
    camera.id = c.camera_id;
    try {
      camera.source = registry.create(c.source_type, c.params, c.context);
      camera.source->start();
    } catch (const Error& e) {
      HULLPOSE_THROW("camera " << c.camera_id << ": cannot start its " << c.source_type
                               << " source: " << e.what());
    }
    cameras_.push_back(std::move(camera));
  }
}

LiveViewProvider::~LiveViewProvider() {
  for (auto& c : cameras_) c.source->stop();
}

bool LiveViewProvider::next(CaptureInstant& out) {
  if (options_.max_instants > 0 && delivered_ >= options_.max_instants) return false;
  out.images.clear();
  for (auto& c : cameras_) {
    camera_node::GrabStatus status = camera_node::GrabStatus::kFrame;
    for (int skip = 0; skip < options_.stride; ++skip) {
      status = c.source->grab(frame_, options_.timeout_ms);
      if (status == camera_node::GrabStatus::kEndOfStream) return false;
      HULLPOSE_THROW_UNLESS(status != camera_node::GrabStatus::kTimeout,
                            "camera " << c.id << ": no frame within " << options_.timeout_ms
                                      << " ms from " << c.source->describe());
    }
    if (status == camera_node::GrabStatus::kCorruptFrame)
      continue;  // logged: this camera misses the instant
    // The source reuses its buffer: the calibration keeps only corners, but detection runs later.
    out.images.push_back({c.id, frame_.image.clone()});
  }
  char name[32];
  std::snprintf(name, sizeof name, "live%05d", delivered_++);
  out.name = name;
  return true;
}

std::string LiveViewProvider::describe() const {
  std::string text = "live cameras:";
  for (const auto& c : cameras_)
    text += " [" + std::to_string(c.id) + ": " + c.source->describe() + "]";
  return text;
}

}  // namespace hullpose::calibrate
