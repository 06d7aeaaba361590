#include "hullpose/import/recording_import.hpp"

#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "hullpose/camera_node/camera_node.hpp"
#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"

namespace hullpose::import {

RecordingImport import_recordings(const RecordingImportOptions& o) {
  HULLPOSE_THROW_UNLESS(!o.node_configs.empty(), "give a --node-config for every camera");
  HULLPOSE_THROW_UNLESS(o.fps > 0, "--fps must be positive, got " << o.fps);
  const DatasetPaths paths(o.out);
  std::filesystem::create_directories(o.out);
  RecordingImport out;
  std::optional<Rig> rig;
  std::vector<int> ids;
  // One in-process bus for every node: nothing leaves the process.
  const std::unique_ptr<bus::Bus> bus = bus::open_bus("memq://");
  for (const std::filesystem::path& file : o.node_configs) {
    camera_node::NodeConfig config = camera_node::load_node_config(file);
    config.lcm.url = "memq://";
    config.trigger.enabled = false;  // frame k of the recording is instant k
    camera_node::CameraNode node(std::move(config), *bus);
    if (!rig) {
      rig = node.rig();
      save_rig(*rig, paths.rig());
    }
    HULLPOSE_THROW_UNLESS(node.rig() == *rig, file.string() << ": rig_file: not the rig of "
                                                            << o.node_configs.front().string());
    const int id = node.config().camera_id;
    ids.push_back(id);
    std::filesystem::create_directories(paths.camera_dir(id));
    node.start();
    camera_node::Frame frame;
    for (;;) {
      const camera_node::GrabStatus s = node.capture(frame, 2000);
      if (s == camera_node::GrabStatus::kEndOfStream) break;
      if (s == camera_node::GrabStatus::kCorruptFrame) {
        ++out.corrupt;  // logged by the source; no mask written: the camera sent nothing
        continue;
      }
      HULLPOSE_THROW_UNLESS(s == camera_node::GrabStatus::kFrame,
                            file.string() << ": camera " << id << ": the source timed out");
      const int f = static_cast<int>(frame.sequence);
      if (o.frames >= 0 && f >= o.frames) break;
      const cv::Mat& mask = node.process(frame, {frame.sequence, frame.capture_utime});
      HULLPOSE_THROW_UNLESS(cv::imwrite(paths.mask(id, f).string(), mask),
                            paths.mask(id, f).string() << ": cannot write");
      if (o.rgb)
        HULLPOSE_THROW_UNLESS(cv::imwrite(paths.rgb(id, f).string(), frame.image),
                              paths.rgb(id, f).string() << ": cannot write");
      ++out.masks;
      out.frames = std::max(out.frames, f + 1);
    }
    node.stop();
  }
  DatasetMeta meta;
  meta.motion = "recorded";
  meta.frames = out.frames;
  meta.fps = o.fps;
  meta.camera_ids = ids;
  write_meta(paths.meta(), meta);
  return out;
}

}  // namespace hullpose::import
