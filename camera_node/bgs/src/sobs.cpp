#include "hullpose/camera_node/sobs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "hullpose/common/check.hpp"

namespace hullpose::camera_node {

SobsParams SobsParams::from(const Params& p) {
  SobsParams s;
  s.epsilon_learn = p.get_double("epsilon_learn", s.epsilon_learn, 1e-6, 3.0);
  s.epsilon_online = p.get_double("epsilon_online", s.epsilon_online, 1e-6, 3.0);
  s.alpha_learn = p.get_double("alpha_learn", s.alpha_learn, 0.0, 1.0);
  s.alpha_online = p.get_double("alpha_online", s.alpha_online, 0.0, 1.0);
  s.shadow_v_min = p.get_double("shadow_v_min", s.shadow_v_min, 0.0, 1.0);
  s.shadow_v_max = p.get_double("shadow_v_max", s.shadow_v_max, 0.0, 1.0);
  s.shadow_s_max = p.get_double("shadow_s_max", s.shadow_s_max, 0.0, 1.0);
  s.shadow_h_max = p.get_double("shadow_h_max", s.shadow_h_max, 0.0, std::numbers::pi);
  p.expect_all_used();
  HULLPOSE_THROW_UNLESS(s.shadow_v_min <= s.shadow_v_max,
                        p.scope() << ".shadow_v_min: must not exceed shadow_v_max (" << s.shadow_v_max << ")");
  return s;
}

void Sobs::begin_learning(cv::Size size) {
  size_ = size;
  learnt_ = 0;
  map_.assign(static_cast<size_t>(size.area()) * 9, Cell{0, 0, 0, 0});
  cone_.assign(static_cast<size_t>(size.area()), Cell{0, 0, 0, 0});
  learn_mask_.create(size, CV_8UC1);
}

// The HSV cone point of a BGR pixel. Hue and chroma come from the opponent axes
// (R - (G+B)/2, sqrt(3)/2 (G - B)) — the chroma plane of the HSV hexcone (Hanbury 2003) —
// so no trigonometry per pixel; their length is max - min = S V up to the hexagon-to-circle
// factor (between sqrt(3)/2 and 1).
void Sobs::to_cone(const cv::Mat& bgr) {
  constexpr float k = 1.f / 255.f, half_sqrt3 = 0.8660254f;
  for (int y = 0; y < size_.height; ++y) {
    const uint8_t* row = bgr.ptr<uint8_t>(y);
    Cell* out = &cone_[static_cast<size_t>(y) * static_cast<size_t>(size_.width)];
    for (int x = 0; x < size_.width; ++x) {
      const float b = row[3 * x] * k, g = row[3 * x + 1] * k, r = row[3 * x + 2] * k;
      out[x] = Cell{r - 0.5f * (g + b), half_sqrt3 * (g - b), std::max(r, std::max(g, b)), 0.f};
    }
  }
}

void Sobs::learn(const cv::Mat& bgr) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_);
  to_cone(bgr);
  if (learnt_ == 0) {  // the map starts as nine copies of the first frame
    const size_t mw = 3 * static_cast<size_t>(size_.width);
    for (int y = 0; y < size_.height; ++y)
      for (int x = 0; x < size_.width; ++x) {
        const Cell c = cone_[static_cast<size_t>(y) * static_cast<size_t>(size_.width) + static_cast<size_t>(x)];
        for (size_t b = 0; b < 3; ++b)
          for (size_t a = 0; a < 3; ++a) map_[(3 * static_cast<size_t>(y) + b) * mw + 3 * static_cast<size_t>(x) + a] = c;
      }
  }
  ++learnt_;
  const double alpha = std::max(params_.alpha_online, params_.alpha_learn / learnt_);
  step(static_cast<float>(params_.epsilon_learn), static_cast<float>(alpha), nullptr);
}

void Sobs::end_learning() { HULLPOSE_THROW_UNLESS(learnt_ > 0, "sobs: no background frame was learnt"); }

void Sobs::apply(const cv::Mat& bgr, cv::Mat& mask) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_ && mask.size() == size_ && mask.type() == CV_8UC1);
  to_cone(bgr);
  step(static_cast<float>(params_.epsilon_online), static_cast<float>(params_.alpha_online), &mask);
}

namespace {

inline float dist2(Sobs::Cell a, Sobs::Cell b) {
  const Sobs::Cell d = a - b;
  const Sobs::Cell d2 = d * d;
  return d2[0] + d2[1] + d2[2];
}

}  // namespace

// One pass of the network over the current frame (cone_). Written by hand: it is the method
// itself, and the best-match search and neighbourhood update are per-pixel data-dependent, which
// no OpenCV primitive expresses. Scalar over pixels, SIMD over a cell's components.
void Sobs::step(float epsilon, float alpha, cv::Mat* mask) {
  const int w = size_.width, h = size_.height;
  const size_t mw = 3 * static_cast<size_t>(w);
  const int mw_i = 3 * w, mh_i = 3 * h;
  // Gaussian neighbourhood weights (1 2 1; 2 4 2; 1 2 1) / 4: the best match moves by alpha.
  const float wk[3][3] = {{0.25f, 0.5f, 0.25f}, {0.5f, 1.f, 0.5f}, {0.25f, 0.5f, 0.25f}};
  Cell aw[3][3];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const float s = alpha * wk[j][i];
      aw[j][i] = Cell{s, s, s, s};
    }
  const float v_min = static_cast<float>(params_.shadow_v_min), v_max = static_cast<float>(params_.shadow_v_max);
  const float s_max = static_cast<float>(params_.shadow_s_max), h_max = static_cast<float>(params_.shadow_h_max);
  for (int y = 0; y < h; ++y) {
    uint8_t* out = mask ? mask->ptr<uint8_t>(y) : nullptr;
    const Cell* in = &cone_[static_cast<size_t>(y) * static_cast<size_t>(w)];
    for (int x = 0; x < w; ++x) {
      const Cell p = in[x];
      const size_t base = 3 * static_cast<size_t>(y) * mw + 3 * static_cast<size_t>(x);
      float best = std::numeric_limits<float>::max();
      int best_a = 1, best_b = 1;
      for (int b = 0; b < 3; ++b) {
        const Cell* row = &map_[base + static_cast<size_t>(b) * mw];
        for (int a = 0; a < 3; ++a) {
          const float d = dist2(row[a], p);
          if (d < best) {
            best = d;
            best_a = a;
            best_b = b;
          }
        }
      }
      if (best <= epsilon) {
        if (out) out[x] = 0;
        const int cx = 3 * x + best_a, cy = 3 * y + best_b;
        for (int dy = -1; dy <= 1; ++dy) {
          const int my = cy + dy;
          if (my < 0 || my >= mh_i) continue;
          Cell* row = &map_[static_cast<size_t>(my) * mw];
          for (int dx = -1; dx <= 1; ++dx) {
            const int mx = cx + dx;
            if (mx < 0 || mx >= mw_i) continue;
            row[mx] += aw[dy + 1][dx + 1] * (p - row[mx]);
          }
        }
        continue;
      }
      if (!out) continue;
      // Shadow: darker than the best match by a bounded ratio, similar saturation and hue.
      const Cell bg = map_[base + static_cast<size_t>(best_b) * mw + static_cast<size_t>(best_a)];
      bool shadow = false;
      if (bg[2] > 1e-3f && p[2] > 1e-3f) {
        const float ratio = p[2] / bg[2];
        const float cp = std::sqrt(p[0] * p[0] + p[1] * p[1]), cb = std::sqrt(bg[0] * bg[0] + bg[1] * bg[1]);
        const float ds = std::abs(cp / p[2] - cb / bg[2]);
        float dh = 0.f;
        if (cp > 0.02f && cb > 0.02f) {  // hue is meaningless for greys
          dh = std::abs(std::atan2(p[1], p[0]) - std::atan2(bg[1], bg[0]));
          dh = std::min(dh, 2.f * std::numbers::pi_v<float> - dh);
        }
        shadow = ratio >= v_min && ratio <= v_max && ds <= s_max && dh <= h_max;
      }
      out[x] = shadow ? 0 : 255;
    }
  }
}

}  // namespace hullpose::camera_node
