#include "hullpose/camera_node/codebook.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/core.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::camera_node {

CodebookParams CodebookParams::from(const Params& p) {
  CodebookParams c;
  c.epsilon_learn = p.get_double("epsilon_learn", c.epsilon_learn, 0.1, 255.0);
  c.epsilon_detect = p.get_double("epsilon_detect", c.epsilon_detect, 0.1, 255.0);
  c.alpha = p.get_double("alpha", c.alpha, 0.05, 1.0);
  c.beta = p.get_double("beta", c.beta, 1.0, 4.0);
  c.max_codewords = p.get_int("max_codewords", c.max_codewords, 1, 16);
  p.expect_all_used();
  return c;
}

void Codebook::begin_learning(cv::Size size) {
  size_ = size;
  frames_ = 0;
  // Learning keeps a few spare codewords beyond what detection keeps, so that a rare colour
  // does not evict a frequent one.
  slots_ = params_.max_codewords + 4;
  learning_.assign(static_cast<size_t>(size.area()) * static_cast<size_t>(slots_), Codeword{});
  count_.assign(static_cast<size_t>(size.area()), 0);
  planes_.clear();
  kmax_ = 0;
  for (auto& s : split_) s.create(size, CV_8UC1);
}

void Codebook::learn(const cv::Mat& bgr) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_);
  const int t = ++frames_;
  const float eps2 = static_cast<float>(params_.epsilon_learn * params_.epsilon_learn);
  const float alpha = static_cast<float>(params_.alpha), beta = static_cast<float>(params_.beta);
  for (int y = 0; y < size_.height; ++y) {
    const uint8_t* row = bgr.ptr<uint8_t>(y);
    for (int x = 0; x < size_.width; ++x) {
      const size_t i =
          static_cast<size_t>(y) * static_cast<size_t>(size_.width) + static_cast<size_t>(x);
      const float b = row[3 * x], g = row[3 * x + 1], r = row[3 * x + 2];
      const float n2 = r * r + g * g + b * b;
      const float bright = std::sqrt(n2);
      Codeword* cw = &learning_[i * static_cast<size_t>(slots_)];
      const int count = count_[i];
      int hit = -1;
      for (int k = 0; k < count && hit < 0; ++k) {
        const Codeword& c = cw[k];
        const float v2 = c.r * c.r + c.g * c.g + c.b * c.b;
        const float dot = r * c.r + g * c.g + b * c.b;
        const float dist2 = n2 - (v2 > 0.f ? dot * dot / v2 : 0.f);
        const float lo = alpha * c.i_max, hi = std::min(beta * c.i_max, c.i_min / alpha);
        if (dist2 <= eps2 && bright >= lo && bright <= hi) hit = k;
      }
      if (hit >= 0) {
        Codeword& c = cw[hit];
        const float w = 1.f / static_cast<float>(c.f + 1);
        c.r += (r - c.r) * w;
        c.g += (g - c.g) * w;
        c.b += (b - c.b) * w;
        c.i_min = std::min(c.i_min, bright);
        c.i_max = std::max(c.i_max, bright);
        c.lambda = std::max(c.lambda, t - c.q);
        c.f += 1;
        c.q = t;
        continue;
      }
      int slot = count;
      if (count == slots_) {  // full: replace the codeword that has been absent longest
        slot = 0;
        for (int k = 1; k < count; ++k)
          if (std::max(cw[k].lambda, t - cw[k].q) > std::max(cw[slot].lambda, t - cw[slot].q))
            slot = k;
      } else {
        count_[i] = static_cast<uint8_t>(count + 1);
      }
      cw[slot] = Codeword{r, g, b, bright, bright, 1, t - 1, t, t};
    }
  }
}

void Codebook::end_learning() {
  HULLPOSE_THROW_UNLESS(frames_ > 0, "codebook: no background frame was learnt");
  const size_t n = static_cast<size_t>(size_.area());
  const float alpha = static_cast<float>(params_.alpha), beta = static_cast<float>(params_.beta);
  kmax_ = params_.max_codewords;
  planes_.assign(static_cast<size_t>(5 * kmax_), std::vector<float>(n, 0.f));
  std::vector<int> order(static_cast<size_t>(slots_));
  for (size_t i = 0; i < n; ++i) {
    Codeword* cw = &learning_[i * static_cast<size_t>(slots_)];
    const int count = count_[i];
    // Temporal filtering: wrap lambda around the learning period, drop codewords absent for
    // more than half of it (moving foreground seen while learning).
    int kept = 0;
    for (int k = 0; k < count; ++k) {
      cw[k].lambda = std::max(cw[k].lambda, frames_ - cw[k].q + cw[k].p - 1);
      if (cw[k].lambda <= std::max(1, frames_ / 2)) order[static_cast<size_t>(kept++)] = k;
    }
    std::sort(order.begin(), order.begin() + kept,
              [cw](int a, int b) { return cw[a].f > cw[b].f; });
    for (int k = 0; k < kmax_; ++k) {
      float* u0 = &planes_[static_cast<size_t>(5 * k)][i];
      if (k >= kept) {  // no codeword: a band that nothing falls in
        planes_[static_cast<size_t>(5 * k + 3)][i] = std::numeric_limits<float>::max();
        planes_[static_cast<size_t>(5 * k + 4)][i] = -1.f;
        *u0 = 0.f;
        continue;
      }
      const Codeword& c = cw[order[static_cast<size_t>(k)]];
      const float norm = std::max(std::sqrt(c.r * c.r + c.g * c.g + c.b * c.b), 1e-3f);
      // Planes hold b, g, r order to match the interleaved frame.
      planes_[static_cast<size_t>(5 * k + 0)][i] = c.b / norm;
      planes_[static_cast<size_t>(5 * k + 1)][i] = c.g / norm;
      planes_[static_cast<size_t>(5 * k + 2)][i] = c.r / norm;
      const float lo = alpha * c.i_max, hi = std::min(beta * c.i_max, c.i_min / alpha);
      planes_[static_cast<size_t>(5 * k + 3)][i] = lo * lo;
      planes_[static_cast<size_t>(5 * k + 4)][i] = hi * hi;
    }
  }
  learning_.clear();
  learning_.shrink_to_fit();
}

double Codebook::mean_codewords() const {
  if (planes_.empty()) return 0.0;
  size_t used = 0;
  for (int k = 0; k < kmax_; ++k)
    for (float hi : planes_[static_cast<size_t>(5 * k + 4)]) used += hi >= 0.f;
  return static_cast<double>(used) / static_cast<double>(size_.area());
}

void Codebook::apply(const cv::Mat& bgr, cv::Mat& mask) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_ && mask.size() == size_ &&
                  mask.type() == CV_8UC1);
  HULLPOSE_ASSERT(mask.isContinuous() && kmax_ > 0);
  cv::split(bgr, split_);
  const size_t n = static_cast<size_t>(size_.area());
  const float eps2 = static_cast<float>(params_.epsilon_detect * params_.epsilon_detect);
  const uint8_t* __restrict pb = split_[0].ptr<uint8_t>();
  const uint8_t* __restrict pg = split_[1].ptr<uint8_t>();
  const uint8_t* __restrict pr = split_[2].ptr<uint8_t>();
  uint8_t* __restrict out = mask.ptr<uint8_t>();
  // Blocks of pixels: codeword k is tested for the whole block at once (vectorised), and the
  // later, rarer codewords only while some pixel of the block is still unmatched. Codewords are
  // sorted by frequency, so most blocks stop after the first.
  constexpr size_t kBlock = 64;
  alignas(64) float b[kBlock], g[kBlock], r[kBlock], n2[kBlock];
  alignas(64) uint8_t matched[kBlock];
  for (size_t start = 0; start < n; start += kBlock) {
    const size_t len = std::min(kBlock, n - start);
    for (size_t j = 0; j < len; ++j) {
      b[j] = pb[start + j];
      g[j] = pg[start + j];
      r[j] = pr[start + j];
      n2[j] = b[j] * b[j] + g[j] * g[j] + r[j] * r[j];
      matched[j] = 0;
    }
    for (int k = 0; k < kmax_; ++k) {
      const float* __restrict ub = planes_[static_cast<size_t>(5 * k + 0)].data() + start;
      const float* __restrict ug = planes_[static_cast<size_t>(5 * k + 1)].data() + start;
      const float* __restrict ur = planes_[static_cast<size_t>(5 * k + 2)].data() + start;
      const float* __restrict lo2 = planes_[static_cast<size_t>(5 * k + 3)].data() + start;
      const float* __restrict hi2 = planes_[static_cast<size_t>(5 * k + 4)].data() + start;
      unsigned all = 1;
      for (size_t j = 0; j < len; ++j) {
        const float dot = b[j] * ub[j] + g[j] * ug[j] + r[j] * ur[j];
        const bool hit = (n2[j] - dot * dot <= eps2) & (n2[j] >= lo2[j]) & (n2[j] <= hi2[j]);
        matched[j] |= static_cast<uint8_t>(hit);
        all &= matched[j];
      }
      if (all) break;
    }
    for (size_t j = 0; j < len; ++j) out[start + j] = matched[j] ? 0 : 255;
  }
}

}  // namespace hullpose::camera_node
