#pragma once
// Writes a one-camera dataset in the layout of docs/conventions.md (rig.yaml,
// cam<ID>/background_*.png, cam<ID>/rgb_*.png, cam<ID>/mask_*.png) from a synthetic-rig sequence,
// plus a node config that replays it. For the camera-node tests.
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "hullpose/common/rig.hpp"
#include "scratch_dir.hpp"
#include "synth_sequence.hpp"

namespace hullpose::test {

inline std::string indexed(const std::filesystem::path& dir, const char* stem, int i) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%06d.png", stem, i);
  return (dir / name).string();
}

inline void write_dataset(const std::filesystem::path& dir, const SynthSequence& seq,
                          int camera_id) {
  std::filesystem::remove_all(dir);
  const std::filesystem::path cam = dir / ("cam" + std::to_string(camera_id));
  std::filesystem::create_directories(cam);
  Rig rig;
  rig.rig_id = "test-rig";
  rig.volume = {{-1000, -1000, 0}, {1000, 1000, 2000}};
  CameraModel c;
  c.id = camera_id;
  c.name = "cam" + std::to_string(camera_id);
  c.width = seq.frames.empty() ? seq.background[0].cols : seq.frames[0].cols;
  c.height = seq.frames.empty() ? seq.background[0].rows : seq.frames[0].rows;
  c.fx = c.fy = 500;
  c.cx = c.width / 2.0;
  c.cy = c.height / 2.0;
  c.t = Eigen::Vector3d(0, 0, 3000);
  rig.cameras.push_back(c);
  save_rig(rig, dir / "rig.yaml");
  for (size_t k = 0; k < seq.background.size(); ++k)
    cv::imwrite(indexed(cam, "background", static_cast<int>(k)), seq.background[k]);
  for (size_t f = 0; f < seq.frames.size(); ++f) {
    cv::imwrite(indexed(cam, "rgb", static_cast<int>(f)), seq.frames[f]);
    cv::imwrite(indexed(cam, "mask", static_cast<int>(f)), seq.truth[f]);
  }
}

// A dataset in this process's own scratch directory (see scratch_dir.hpp), removed with it; as a
// function-local static, written once per test process.
struct ScratchDataset {
  ScratchDir dir;
  ScratchDataset(const std::string& name, const SynthSequence& seq, int camera_id) : dir(name) {
    write_dataset(dir.path, seq, camera_id);
  }
};

// A small synthetic sequence for the node tests.
inline SynthSequence small_synth(cv::Size size, int frames, int background_frames, uint64_t seed) {
  SynthSequenceOptions o;
  o.size = size;
  o.frames = frames;
  o.background_frames = background_frames;
  o.seed = seed;
  return render_synth_sequence(o);
}

// A node config replaying `dir` for camera `camera_id`; `extra` is appended verbatim (inside
// `post:`).
inline std::filesystem::path write_node_config(const std::filesystem::path& dir, int camera_id,
                                               const std::string& method,
                                               const std::string& lcm_url,
                                               const std::string& extra = "") {
  const std::filesystem::path p = dir / "camera.yaml";
  std::ofstream(p) << "%YAML:1.0\n"
                   << "camera_id: " << camera_id << "\n"
                   << "rig_file: rig.yaml\n"
                   << "lcm:\n  url: \"" << lcm_url
                   << "\"\n  queue_depth: 64\n  status_period_ms: 50\n"
                   << "source:\n  type: file\n  path: cam" << camera_id
                   << "/rgb_%06d.png\n  fps: 30\n"
                   << "  start_utime: 1700000000000000\n"
                   << "bgs:\n  method: " << method << "\n  learn_frames: 20\n"
                   << "  background: cam" << camera_id << "/background_%06d.png\n"
                   << "post:\n  min_blob_area: 32\n"
                   << extra;
  return p;
}

}  // namespace hullpose::test
