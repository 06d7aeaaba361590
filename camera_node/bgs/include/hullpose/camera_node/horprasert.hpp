#pragma once
// Horprasert, Harwood & Davis, "A statistical approach for real-time robust background
// subtraction and shadow detection" (ICCV FRAME-RATE workshop 1999; ACCV 2000).
//
// Per pixel, the learnt mean E and standard deviation s of each channel. A frame pixel I is
// compared with E by its brightness distortion alpha (the scale of E closest to I) and its
// chromaticity distortion CD (the distance of I from the line O-E), each measured in units of s.
// Both are normalised by their own RMS over the learning frames, and the thresholds are the
// quantiles of the normalised values over the learning frames that give the requested detection
// rate. Classes: foreground (CD above threshold, or alpha below min_shadow_brightness),
// background (alpha within thresholds), shadow (darker), highlight (brighter).
#include <cstdint>
#include <vector>

#include "hullpose/camera_node/background_subtractor.hpp"

namespace hullpose::camera_node {

struct HorprasertParams {
  double detection_rate = 0.9995;  // fraction of learning pixels that must come out background
  double min_sigma = 2.0;          // floor on the per-channel std. dev. (grey levels): sensor noise
  double min_shadow_brightness = 0.45;  // alpha below this is a dark object, not a shadow
  double cd_scale = 1.5;  // multiplies the learnt chromaticity threshold (margin for drift)

  static HorprasertParams from(const Params& p);
};

class Horprasert final : public BackgroundSubtractor {
 public:
  enum Class : uint8_t { kBackground = 0, kShadow = 1, kHighlight = 2, kForeground = 255 };

  explicit Horprasert(HorprasertParams params = {}) : params_(params) {}
  std::string_view name() const override { return "horprasert"; }
  void begin_learning(cv::Size size) override;
  void learn(const cv::Mat& bgr) override;
  void end_learning() override;
  void apply(const cv::Mat& bgr, cv::Mat& mask) override;

  // The class of every pixel of the last apply() (CV_8UC1 of Class values).
  const cv::Mat& classes() const { return classes_; }

 private:
  HorprasertParams params_;
  cv::Size size_;
  std::vector<cv::Mat> learnt_;  // the learning frames, kept until end_learning()
  // Per-pixel model, structure of arrays so that apply() vectorises:
  // inv_sigma[c] = 1/s_c, m[c] = E_c/s_c, inv_m2 = 1/sum m_c^2,
  // cd2_max = (tau_CD * b)^2, alpha_lo/alpha_hi = 1 + tau_alpha * a (background band).
  std::vector<float> inv_sigma_[3], m_[3], inv_m2_, cd2_max_, alpha_lo_, alpha_hi_;
  cv::Mat planes_[3];
  cv::Mat classes_;
};

}  // namespace hullpose::camera_node
