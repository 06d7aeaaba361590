#pragma once
// Colour frames for background subtraction: a room with a static textured floor and walls,
// the avatar in clothing colours, soft shadows cast on floor and walls by two lamps, slow
// illumination drift, optional exposure flicker and Gaussian sensor noise.
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "hullpose/synth/avatar.hpp"
#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/render.hpp"

namespace hullpose::synth {

struct SceneOptions {
  double room_half_mm = 6500;  // walls at x, y = +-room_half_mm (the cameras stand inside)
  double room_height_mm = 6000;
  double shadow_strength = 0.5;  // fraction of light a full shadow takes away
  double shadow_texel_mm = 60;   // shadow map resolution; the blur makes them soft
  double drift = 0.08;           // relative amplitude of the slow illumination drift
  double drift_period_s = 40;
  double flicker = 0;        // sigma of the relative per-frame exposure error (0 = off)
  double noise_sigma = 2.0;  // sensor noise, grey levels
};

class Scene {
 public:
  // Clothing and skin colours and the textures are drawn from `seed`.
  Scene(const SceneOptions& options, uint64_t seed);
  const SceneOptions& options() const { return options_; }
  uint64_t seed() const { return seed_; }

  // Shadow map of the avatar on floor and walls (CV_32FC1, 0 lit .. 1 fully shadowed), blurred.
  void shadows(const std::vector<Primitive>& primitives, cv::Mat& atlas) const;

  // What a camera sees of the empty room: colour (CV_32FC3, BGR) and, per pixel, where in the
  // shadow map it looks (CV_32FC2, for cv::remap; off-map for the ceiling).
  struct Backdrop {
    cv::Mat colour;
    cv::Mat shadow_map;
  };
  Backdrop backdrop(const ViewRenderer& view) const;

  // Exposure of `camera` at time t: drift plus, if enabled, a per-frame flicker.
  double gain(int camera, int frame, double t_s) const;
  cv::Vec3f colour(Material m) const { return palette_[static_cast<size_t>(m)]; }

 private:
  SceneOptions options_;
  uint64_t seed_;
  std::array<cv::Vec3f, kNumMaterials> palette_;
  std::vector<Eigen::Vector3d> lights_;
  std::vector<double> light_weight_;
};

// One camera of a synthetic scene, rendered on demand: the synthetic source of a camera node.
// Borrows the motion and the scene, which must outlive it. Buffers are reused between frames.
class CameraRenderer {
 public:
  CameraRenderer(const Motion& motion, const BodyShape& body, const CameraModel& camera,
                 const Scene& scene, double fps);
  const CameraModel& camera() const { return view_.camera(); }

  // Frame `frame` at time frame / fps: colour (CV_8UC3, BGR) and the exact mask (CV_8UC1).
  void render(int frame, cv::Mat& bgr, cv::Mat& mask);
  // The same at an explicit time (trigger jitter) with the avatar and its shadow map given.
  void render_posed(int frame, double t_s, const std::vector<Primitive>& primitives,
                    const cv::Mat& shadow_atlas, cv::Mat& bgr, cv::Mat& mask);
  // The empty room, as background-learning frames; index k is taken at time -k seconds.
  void render_background(int index, cv::Mat& bgr);
  // A camera gone dark: sensor noise on black.
  void render_dark(int frame, cv::Mat& bgr);

 private:
  void compose(int frame, double t_s, bool person, cv::Mat& bgr);

  const Motion& motion_;
  BodyShape body_;
  const Scene& scene_;
  double fps_;
  ViewRenderer view_;
  Scene::Backdrop backdrop_;
  JointPositions joints_{};
  std::vector<Primitive> primitives_;
  cv::Mat atlas_, shadow_, material_, facing_;
  cv::Mat noise_;  // CV_16SC3 bank of sensor noise, a little larger than the image
};

}  // namespace hullpose::synth
