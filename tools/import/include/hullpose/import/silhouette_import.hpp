#pragma once
// A dataset (docs/conventions.md) from silhouettes recorded by another system: per camera and
// frame one image found by a pattern (pattern.hpp), plus a rig whose camera ids are the
// pattern's camera numbers. Each image is re-encoded as our mask (8-bit, 255 = person): pixels
// brighter than `threshold` in grey are the person. The result replays with
// `hullpose-fusion-host --replay DIR` and scores with `hullpose-eval` (no ground truth).
#include <filesystem>
#include <string>

#include "hullpose/common/rig.hpp"

namespace hullpose::import {

struct SilhouetteImportOptions {
  std::filesystem::path rig;  // our rig file (e.g. from import_rig)
  std::string pattern;        // {N} camera number = rig camera id, {F} frame number
  std::filesystem::path out;  // dataset folder, created
  int first = 0;              // first source frame number
  int frames = -1;            // < 0: until no camera has a file for the next frame number
  double fps = 30;
  int threshold = 127;
  std::string motion = "imported";  // meta.json "motion"
};

struct SilhouetteImport {
  int frames = 0;
  int masks = 0;
  int missing = 0;     // (camera, frame) without a file: that camera sent nothing
  int unreadable = 0;  // corrupt or truncated files: also a camera that sent nothing (logged)
};

// Throws hullpose::Error on a bad rig, an unwritable output or a mask whose size is not the
// rig's for that camera (a wrong pattern or rig, not a bad frame).
SilhouetteImport import_silhouettes(const SilhouetteImportOptions& options);

}  // namespace hullpose::import
