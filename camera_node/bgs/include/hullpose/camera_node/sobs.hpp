#pragma once
// Maddalena & Petrosino, "A self-organizing approach to background subtraction for visual
// surveillance applications", IEEE Trans. Image Processing 17(7), 2008 (SOBS).
//
// Each pixel owns an n x n block (n = 3) of weight vectors in a neural map of 3W x 3H cells,
// colours in the HSV cone. A pixel matches when its best-matching weight is within epsilon; the
// best match and its 3 x 3 neighbourhood in the map — which reaches into the neighbouring
// pixels' blocks, the method's spatial coherence — move towards the pixel by alpha * w with
// Gaussian weights w. A non-matching pixel whose value is a darker, similar-hue version of its
// best match is shadow (Cucchiara's HSV test) and not learnt; otherwise it is foreground.
// Learning: the map starts as copies of the first frame; the learning frames then train it
// with epsilon_learn and a learning rate falling as alpha_learn / t to alpha_online.
#include <vector>

#include "hullpose/camera_node/background_subtractor.hpp"

namespace hullpose::camera_node {

struct SobsParams {
  double epsilon_learn = 0.02;  // squared HSV-cone distance (cone of radius and height 1)
  double epsilon_online = 0.006;
  double alpha_learn = 0.5;    // learning rate at the first learning frame
  double alpha_online = 0.05;  // learning rate afterwards
  double shadow_v_min = 0.4;   // shadow: V ratio to the background in [shadow_v_min, shadow_v_max]
  double shadow_v_max = 0.97;
  double shadow_s_max = 0.12;  // |S - S_bg| at most
  double shadow_h_max = 0.6;   // |H - H_bg| at most (radians)

  static SobsParams from(const Params& p);
};

class Sobs final : public BackgroundSubtractor {
 public:
  // Four floats as one GCC/Clang vector, so that the arithmetic below is SIMD on x86 and ARM.
  using Vec4 = float __attribute__((vector_size(16)));
  // Three horizontally adjacent cells of the map (one pixel's slots in one row of its 3 x 3
  // block) in SoA form: lanes 0..2 are the cells, lane 3 is padding that never matches.
  // Colours are points of the HSV cone: chroma vector (S V cos H, S V sin H) and value V.
  struct Block {
    Vec4 x, y, v;
  };

  explicit Sobs(SobsParams params = {}) : params_(params) {}
  std::string_view name() const override { return "sobs"; }
  void begin_learning(cv::Size size) override;
  void learn(const cv::Mat& bgr) override;
  void end_learning() override;
  void apply(const cv::Mat& bgr, cv::Mat& mask) override;

 private:
  void step(const cv::Mat& bgr, float epsilon, float alpha, cv::Mat* mask);

  SobsParams params_;
  cv::Size size_;
  int learnt_ = 0;
  // The map: (3H + 2) rows of (W + 2) blocks; the outer ring is a margin that absorbs the
  // neighbourhood updates of edge pixels so the inner loop has no bounds checks.
  std::vector<Block> map_;
};

}  // namespace hullpose::camera_node
