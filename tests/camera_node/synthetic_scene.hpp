#pragma once
// A small seeded generator of RGB test sequences for background subtraction, with exact
// ground-truth masks: a textured static background (walls and floor), a walking person-like
// shape with textured clothes, a soft cast shadow on the floor and wall, a slow illumination
// drift (slightly coloured) and Gaussian sensor noise. Learning frames show the empty scene
// under the starting light.
#include <cstdint>
#include <opencv2/core/mat.hpp>

namespace hullpose::test {

struct SceneOptions {
  cv::Size size{640, 480};
  uint64_t seed = 1;
  int frames = 40;             // test frames (the person walks across in this many)
  double drift = 0.10;         // peak relative change of the light over the sequence
  double shadow_strength = 0.45;  // 0: no shadow; light removed in the shadow's core
  double noise_sigma = 2.5;    // grey levels
};

class SyntheticScene {
 public:
  explicit SyntheticScene(SceneOptions options);
  const SceneOptions& options() const { return options_; }
  // Empty scene, starting light, fresh noise for each k.
  void background_frame(int k, cv::Mat& bgr) const;
  // Test frame f (0..frames-1): BGR image and the person's exact mask (255 = person).
  void frame(int f, cv::Mat& bgr, cv::Mat& mask) const;

 private:
  void person(int f, cv::Mat& mask, cv::Mat& shadow) const;
  void finish(cv::Mat& scene_f32, double gain_phase, uint64_t noise_seed, cv::Mat& bgr) const;

  SceneOptions options_;
  cv::Mat background_;  // CV_32FC3, noiseless
  cv::Mat clothes_;     // CV_32FC3, the person's texture (full frame, sampled under the mask)
};

// Pixel counts of a mask against ground truth.
struct Score {
  int64_t tp = 0, fp = 0, fn = 0;
  void add(const cv::Mat& mask, const cv::Mat& truth);
  double precision() const { return tp + fp ? static_cast<double>(tp) / static_cast<double>(tp + fp) : 1.0; }
  double recall() const { return tp + fn ? static_cast<double>(tp) / static_cast<double>(tp + fn) : 1.0; }
  double f1() const {
    const double p = precision(), r = recall();
    return p + r > 0 ? 2 * p * r / (p + r) : 0.0;
  }
};

}  // namespace hullpose::test
