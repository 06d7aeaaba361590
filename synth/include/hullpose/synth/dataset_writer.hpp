#pragma once
// Renders a whole synthetic dataset to disk in the layout of docs/conventions.md: rig.yaml
// (the perturbed one when calibration faults are asked for; the true one is rig_true.yaml),
// meta.json, ground_truth.csv, cam<ID>/mask_*.png and, with rgb, cam<ID>/rgb_*.png and
// cam<ID>/background_*.png.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "hullpose/synth/avatar.hpp"
#include "hullpose/synth/faults.hpp"
#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/scene.hpp"

namespace hullpose::synth {

struct SynthConfig {
  std::string motion = "walk";   // built-in name or .bvh path
  MotionOptions motion_options;  // centre_mm is set to the capture volume's floor centre
  BodyShape body;                // stature_mm is taken from the motion
  std::filesystem::path out;
  int frames = 0;  // 0 = the whole clip (built-in motions: 300)
  double fps = 30;
  std::string rig = "thesis8";  // or a rig file
  bool rgb = false;
  int backgrounds = 10;  // background-only frames per camera (with rgb)
  SceneOptions scene;
  FaultSpec faults;
  uint64_t seed = 1;
  int64_t start_utime = 1'700'000'000'000'000;
  int png_compression = 1;  // zlib level: masks compress well even at 1
};

struct SynthSummary {
  int frames = 0;
  int cameras = 0;
  double stature_mm = 0;
  std::string motion;
  double seconds = 0;
};

// progress(done, total) is called from the calling thread after each frame.
SynthSummary write_dataset(const SynthConfig& config,
                           const std::function<void(int, int)>& progress = {});

}  // namespace hullpose::synth
