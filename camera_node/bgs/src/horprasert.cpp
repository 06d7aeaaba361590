#include "hullpose/camera_node/horprasert.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::camera_node {

HorprasertParams HorprasertParams::from(const Params& p) {
  HorprasertParams h;
  h.detection_rate = p.get_double("detection_rate", h.detection_rate, 0.5, 1.0);
  h.min_sigma = p.get_double("min_sigma", h.min_sigma, 0.1, 64.0);
  h.min_shadow_brightness =
      p.get_double("min_shadow_brightness", h.min_shadow_brightness, 0.0, 1.0);
  h.cd_scale = p.get_double("cd_scale", h.cd_scale, 0.1, 100.0);
  p.expect_all_used();
  return h;
}

void Horprasert::begin_learning(cv::Size size) {
  size_ = size;
  learnt_.clear();
  const size_t n = static_cast<size_t>(size.area());
  for (int c = 0; c < 3; ++c) {
    inv_sigma_[c].assign(n, 0.f);
    m_[c].assign(n, 0.f);
    planes_[c].create(size, CV_8UC1);
  }
  inv_m2_.assign(n, 0.f);
  cd2_max_.assign(n, 0.f);
  alpha_lo_.assign(n, 0.f);
  alpha_hi_.assign(n, 0.f);
  classes_.create(size, CV_8UC1);
}

void Horprasert::learn(const cv::Mat& bgr) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_);
  learnt_.push_back(bgr.clone());
}

namespace {

// Value below which `fraction` of the samples lie (samples are reordered).
float quantile(std::vector<float>& samples, double fraction) {
  if (samples.empty()) return 0.f;
  const size_t k = std::min(samples.size() - 1,
                            static_cast<size_t>(fraction * static_cast<double>(samples.size())));
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k),
                   samples.end());
  return samples[k];
}

}  // namespace

void Horprasert::end_learning() {
  HULLPOSE_THROW_UNLESS(!learnt_.empty(), "horprasert: no background frame was learnt");
  const size_t n = static_cast<size_t>(size_.area());
  const double frames = static_cast<double>(learnt_.size());
  const float min_sigma = static_cast<float>(params_.min_sigma);

  // Pass 1: mean and standard deviation per pixel and channel.
  std::vector<double> sum[3], sum2[3];
  for (int c = 0; c < 3; ++c) {
    sum[c].assign(n, 0.0);
    sum2[c].assign(n, 0.0);
  }
  for (const cv::Mat& f : learnt_) {
    for (int y = 0; y < size_.height; ++y) {
      const uint8_t* row = f.ptr<uint8_t>(y);
      for (int x = 0; x < size_.width; ++x) {
        const size_t i =
            static_cast<size_t>(y) * static_cast<size_t>(size_.width) + static_cast<size_t>(x);
        for (int c = 0; c < 3; ++c) {
          const double v = row[3 * x + c];
          sum[c][i] += v;
          sum2[c][i] += v * v;
        }
      }
    }
  }
  std::vector<float> mean[3];
  for (int c = 0; c < 3; ++c) {
    mean[c].resize(n);
    for (size_t i = 0; i < n; ++i) {
      const double mu = sum[c][i] / frames;
      const double var = std::max(0.0, sum2[c][i] / frames - mu * mu);
      const float sigma = std::max(min_sigma, static_cast<float>(std::sqrt(var)));
      mean[c][i] = static_cast<float>(mu);
      inv_sigma_[c][i] = 1.f / sigma;
      m_[c][i] = static_cast<float>(mu) / sigma;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const float m2 = m_[0][i] * m_[0][i] + m_[1][i] * m_[1][i] + m_[2][i] * m_[2][i];
    inv_m2_[i] = 1.f / std::max(m2, 1e-6f);
  }

  // Pass 2: alpha and CD of every learning pixel; a = RMS(alpha - 1), b = RMS(CD) per pixel.
  std::vector<float> alpha(n * learnt_.size()), cd(n * learnt_.size());
  std::vector<double> a2(n, 0.0), b2(n, 0.0);
  for (size_t f = 0; f < learnt_.size(); ++f) {
    for (int y = 0; y < size_.height; ++y) {
      const uint8_t* row = learnt_[f].ptr<uint8_t>(y);
      for (int x = 0; x < size_.width; ++x) {
        const size_t i =
            static_cast<size_t>(y) * static_cast<size_t>(size_.width) + static_cast<size_t>(x);
        float xs[3], dot = 0.f;
        for (int c = 0; c < 3; ++c) {
          xs[c] = static_cast<float>(row[3 * x + c]) * inv_sigma_[c][i];
          dot += xs[c] * m_[c][i];
        }
        const float al = dot * inv_m2_[i];
        float cd2 = 0.f;
        for (int c = 0; c < 3; ++c) cd2 += (xs[c] - al * m_[c][i]) * (xs[c] - al * m_[c][i]);
        alpha[f * n + i] = al;
        cd[f * n + i] = std::sqrt(cd2);
        a2[i] += static_cast<double>((al - 1.f) * (al - 1.f));
        b2[i] += static_cast<double>(cd2);
      }
    }
  }
  // Floors keep a perfectly still pixel (clipped at 0 or 255, the thesis' trouble) from getting
  // a zero-width band: one grey level of noise relative to the mean.
  std::vector<float> a(n), b(n);
  for (size_t i = 0; i < n; ++i) {
    const float mu_norm =
        std::sqrt(mean[0][i] * mean[0][i] + mean[1][i] * mean[1][i] + mean[2][i] * mean[2][i]);
    a[i] = std::max(static_cast<float>(std::sqrt(a2[i] / frames)), 1.f / std::max(mu_norm, 1.f));
    b[i] = std::max(static_cast<float>(std::sqrt(b2[i] / frames)), 0.1f);
  }
  // Normalised distortions of all learning pixels; thresholds are their quantiles.
  for (size_t f = 0; f < learnt_.size(); ++f) {
    for (size_t i = 0; i < n; ++i) {
      alpha[f * n + i] = (alpha[f * n + i] - 1.f) / a[i];
      cd[f * n + i] /= b[i];
    }
  }
  const double tail = 1.0 - params_.detection_rate;
  const float tau_cd = quantile(cd, params_.detection_rate) * static_cast<float>(params_.cd_scale);
  const float tau_lo = quantile(alpha, tail / 2);
  const float tau_hi = quantile(alpha, 1.0 - tail / 2);
  for (size_t i = 0; i < n; ++i) {
    cd2_max_[i] = (tau_cd * b[i]) * (tau_cd * b[i]);
    alpha_lo_[i] = 1.f + tau_lo * a[i];
    alpha_hi_[i] = 1.f + tau_hi * a[i];
  }
  learnt_.clear();
  learnt_.shrink_to_fit();
}

namespace {

// Hot loop: straight-line float arithmetic, no branches, every pointer a __restrict parameter
// (GCC honours restrict only on parameters), so it vectorises.
void classify(size_t n, const uint8_t* __restrict p0, const uint8_t* __restrict p1,
              const uint8_t* __restrict p2, const float* __restrict is0,
              const float* __restrict is1, const float* __restrict is2, const float* __restrict m0,
              const float* __restrict m1, const float* __restrict m2, const float* __restrict im2,
              const float* __restrict cdmax, const float* __restrict alo,
              const float* __restrict ahi, float min_alpha, uint8_t* __restrict cls,
              uint8_t* __restrict out) {
  for (size_t i = 0; i < n; ++i) {
    const float x0 = static_cast<float>(p0[i]) * is0[i];
    const float x1 = static_cast<float>(p1[i]) * is1[i];
    const float x2 = static_cast<float>(p2[i]) * is2[i];
    const float al = (x0 * m0[i] + x1 * m1[i] + x2 * m2[i]) * im2[i];
    const float d0 = x0 - al * m0[i], d1 = x1 - al * m1[i], d2 = x2 - al * m2[i];
    const float cd2 = d0 * d0 + d1 * d1 + d2 * d2;
    const int fg = (cd2 > cdmax[i]) | (al < min_alpha);
    const int bg = (al >= alo[i]) & (al <= ahi[i]);
    // kForeground if fg, else kBackground if bg, else kShadow (darker) or kHighlight, as
    // arithmetic.
    const int fg_bits = -fg & 0xff;
    cls[i] = static_cast<uint8_t>(((2 - (al < 1.f)) * (1 - bg)) | fg_bits);
    out[i] = static_cast<uint8_t>(fg_bits);
  }
}

}  // namespace

void Horprasert::apply(const cv::Mat& bgr, cv::Mat& mask) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_ && mask.size() == size_ &&
                  mask.type() == CV_8UC1);
  HULLPOSE_ASSERT(mask.isContinuous());
  cv::split(bgr, planes_);  // SIMD in OpenCV; planes_ are preallocated
  classify(static_cast<size_t>(size_.area()), planes_[0].ptr<uint8_t>(), planes_[1].ptr<uint8_t>(),
           planes_[2].ptr<uint8_t>(), inv_sigma_[0].data(), inv_sigma_[1].data(),
           inv_sigma_[2].data(), m_[0].data(), m_[1].data(), m_[2].data(), inv_m2_.data(),
           cd2_max_.data(), alpha_lo_.data(), alpha_hi_.data(),
           static_cast<float>(params_.min_shadow_brightness), classes_.ptr<uint8_t>(),
           mask.ptr<uint8_t>());
}

}  // namespace hullpose::camera_node
