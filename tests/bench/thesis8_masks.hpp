#pragma once
// Human silhouettes from the synthetic rig: every frame of CMU 55_01 ("dance, whirl") seen by
// the 8 thesis cameras at 800x600, in stream order (frame by frame, camera by camera). Shared by
// bench_codec (encoded sizes, throughput) and bench_auth (the MAC over a real message stream).
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/render.hpp"
#include "hullpose/synth/rig_gen.hpp"

namespace hullpose::bench {

struct Thesis8Masks {
  int cameras = 0;
  std::vector<cv::Mat> masks;  // masks[frame * cameras + camera]
};

inline Thesis8Masks render_thesis8_55_01() {
  using namespace hullpose::synth;
  Thesis8Masks out;
  const hullpose::Rig rig = make_ring_rig({});
  const auto motion =
      load_bvh_motion(std::filesystem::path(HULLPOSE_SHARED_DIR) / "data/mocap/55_01.bvh", {});
  BodyShape body;
  body.stature_mm = motion->stature_mm();
  std::vector<ViewRenderer> views;
  for (const auto& c : rig.cameras) views.emplace_back(c);
  out.cameras = static_cast<int>(views.size());
  hullpose::JointPositions q;
  std::vector<Primitive> prims;
  const int frames = motion->frame_count(30);
  for (int f = 0; f < frames; ++f) {
    motion->sample(f / 30.0, q);
    pose_avatar(body, q, prims);
    for (auto& view : views) {
      out.masks.emplace_back();
      view.render_mask(prims, out.masks.back());
    }
  }
  return out;
}

}  // namespace hullpose::bench
