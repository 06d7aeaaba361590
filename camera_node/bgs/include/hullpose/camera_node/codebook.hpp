#pragma once
// Kim, Chalidabhongse, Harwood & Davis, "Real-time foreground-background segmentation using
// codebook model", Real-Time Imaging 11 (2005).
//
// Each pixel keeps a small codebook of codewords (mean colour v, brightness range [Imin, Imax],
// frequency f, maximum negative run-length lambda, first and last access p, q). A pixel x
// matches a codeword if colordist(x, v) <= epsilon and its brightness |x| lies in
// [alpha Imax, min(beta Imax, Imin / alpha)]. After learning, codewords whose lambda exceeds
// half the learning frames are dropped (temporal filtering); a pixel is foreground when no
// codeword matches. The brightness band is what absorbs slow illumination drift and shadows.
#include <cstdint>
#include <vector>

#include "hullpose/camera_node/background_subtractor.hpp"

namespace hullpose::camera_node {

struct CodebookParams {
  double epsilon_learn = 12.0;   // colour distortion bound while learning (grey levels)
  double epsilon_detect = 16.0;  // ... while detecting
  double alpha = 0.45;    // lower brightness bound as a fraction of Imax (shadows down to it)
  double beta = 1.3;      // upper brightness bound as a fraction of Imax (highlights up to it)
  int max_codewords = 4;  // per pixel; the most frequent are kept

  static CodebookParams from(const Params& p);
};

class Codebook final : public BackgroundSubtractor {
 public:
  explicit Codebook(CodebookParams params = {}) : params_(params) {}
  std::string_view name() const override { return "codebook"; }
  void begin_learning(cv::Size size) override;
  void learn(const cv::Mat& bgr) override;
  void end_learning() override;
  void apply(const cv::Mat& bgr, cv::Mat& mask) override;

  // Mean number of codewords per pixel after learning.
  double mean_codewords() const;

 private:
  struct Codeword {
    float r, g, b;       // mean colour
    float i_min, i_max;  // brightness range seen
    int32_t f, lambda, p, q;
  };

  CodebookParams params_;
  cv::Size size_;
  int frames_ = 0;
  int slots_ = 0;                   // codewords per pixel in the learning store
  std::vector<Codeword> learning_;  // pixel-major, slots_ per pixel
  std::vector<uint8_t> count_;      // codewords per pixel
  // Detection model, structure of arrays, codewords sorted by frequency (most frequent first):
  // for codeword k, plane 5k+0..2 = unit mean colour, 5k+3 = low^2, 5k+4 = high^2 brightness bound.
  std::vector<std::vector<float>> planes_;
  int kmax_ = 0;
  cv::Mat split_[3];
};

}  // namespace hullpose::camera_node
