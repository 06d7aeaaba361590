#pragma once
// The One Euro filter (Casiez, Roussel and Vogel, CHI 2012) on 3-D joint positions: a causal
// low-pass whose cut-off rises with speed, so a still joint is smoothed hard (jitter) and a
// moving one barely (lag). Fixed state, no allocation.
#include <Eigen/Core>
#include <array>
#include <cmath>

#include "hullpose/common/joints.hpp"

namespace hullpose::pose {

struct OneEuroParams {
  // Cut-off at rest (Hz) and its rise per unit speed (Hz per mm/s). At 30 fps a 1.5 Hz cut-off
  // removes voxel-scale jitter of a still joint; beta = 0.02 puts the cut-off at ~20 Hz
  // (near no smoothing at 30 fps) for a joint moving 1 m/s, so a moving joint lags well under
  // a frame. The derivative is smoothed at 1 Hz, the paper's recommendation.
  double min_cutoff_hz = 1.5;
  double beta = 0.02;
  double derivative_cutoff_hz = 1.0;
};

class OneEuroFilter {
 public:
  explicit OneEuroFilter(OneEuroParams params = {}) : params_(params) {}
  void reset() { started_ = false; }
  template <size_t N>
  void apply(std::array<Eigen::Vector3d, N>& x, double dt_s) {
    static_assert(N <= kNumJoints);
    if (!started_ || dt_s <= 0) {
      for (size_t j = 0; j < N; ++j) {
        value_[j] = x[j];
        derivative_[j].setZero();
      }
      started_ = true;
      return;
    }
    const double ad = alpha(params_.derivative_cutoff_hz, dt_s);
    for (size_t j = 0; j < N; ++j) {
      const Eigen::Vector3d d = (x[j] - value_[j]) / dt_s;
      derivative_[j] += ad * (d - derivative_[j]);
      const double cutoff = params_.min_cutoff_hz + params_.beta * derivative_[j].norm();
      value_[j] += alpha(cutoff, dt_s) * (x[j] - value_[j]);
      x[j] = value_[j];
    }
  }

 private:
  static double alpha(double cutoff_hz, double dt_s) {
    const double tau = 1.0 / (2 * M_PI * cutoff_hz);
    return 1.0 / (1.0 + tau / dt_s);
  }
  OneEuroParams params_;
  bool started_ = false;
  std::array<Eigen::Vector3d, kNumJoints> value_{}, derivative_{};
};

}  // namespace hullpose::pose
