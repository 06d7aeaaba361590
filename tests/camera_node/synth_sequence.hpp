#pragma once
// RGB test sequences from the synthetic rig's renderer (tools/synth): one ring camera of a
// thesis-like rig at the requested resolution watching a walking avatar in a textured room with
// soft shadows from two lamps, illumination drift and sensor noise; exact ground-truth masks.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/rig_gen.hpp"
#include "hullpose/synth/scene.hpp"

namespace hullpose::test {

struct SynthSequence {
  std::vector<cv::Mat> background, frames, truth;
};

struct SynthSequenceOptions {
  cv::Size size{640, 480};
  uint64_t seed = 1;
  int background_frames = 30;
  int frames = 30;
  int camera = 0;
  double fps = 30;
  double drift = 0.10;        // relative amplitude of the illumination drift ...
  double drift_period_s = 8;  // ... fast enough that a one-second sequence sees it
  double shadow_strength = 0.5;
  double noise_sigma = 2.0;
  const char* motion = "walk";
};

inline SynthSequence render_synth_sequence(const SynthSequenceOptions& o) {
  synth::RingRigSpec spec;
  spec.width = o.size.width;
  spec.height = o.size.height;
  const Rig rig = synth::make_ring_rig(spec);
  synth::MotionOptions mo;
  const Eigen::Vector3d c = 0.5 * (rig.volume.min_mm + rig.volume.max_mm);
  mo.centre_mm = Eigen::Vector3d(c.x(), c.y(), rig.volume.min_mm.z());
  const auto motion = synth::make_motion(o.motion, mo);
  synth::SceneOptions so;
  so.drift = o.drift;
  so.drift_period_s = o.drift_period_s;
  so.shadow_strength = o.shadow_strength;
  so.noise_sigma = o.noise_sigma;
  const synth::Scene scene(so, o.seed);
  synth::BodyShape body;
  body.stature_mm = motion->stature_mm();
  synth::CameraRenderer renderer(*motion, body, *rig.find(o.camera), scene, o.fps);
  SynthSequence s;
  for (int k = 0; k < o.background_frames; ++k)
    renderer.render_background(k, s.background.emplace_back());
  for (int f = 0; f < o.frames; ++f) {
    s.frames.emplace_back();
    s.truth.emplace_back();
    renderer.render(f, s.frames.back(), s.truth.back());
  }
  return s;
}

}  // namespace hullpose::test
