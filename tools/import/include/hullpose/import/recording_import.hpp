#pragma once
// A dataset (docs/conventions.md) from recorded colour video through the camera node's own
// pipeline: each camera node config (its file source, background, method, clean-up) runs
// in-process (LCM memq://, no trigger), and every frame's colour image and published silhouette
// are written as cam<ID>/rgb_*.png and cam<ID>/mask_*.png. The live rig and this dataset then see
// the same silhouettes: `--replay` runs on it and hullpose-eval scores live estimates against it.
#include <filesystem>
#include <vector>

namespace hullpose::import {

struct RecordingImportOptions {
  std::vector<std::filesystem::path> node_configs;  // one per camera, one rig
  std::filesystem::path out;
  int frames = -1;  // < 0: to the end of each source
  double fps = 30;  // meta.json (the recording's rate)
  bool rgb = true;  // also write the colour frames (for the report's pictures)
};

struct RecordingImport {
  int frames = 0;
  int masks = 0;
  int corrupt = 0;  // frames that did not decode: that camera missing for them
};

// Throws hullpose::Error naming the config file (or the camera) on a bad config, an absent
// source, or node configs of different rigs.
RecordingImport import_recordings(const RecordingImportOptions& options);

}  // namespace hullpose::import
