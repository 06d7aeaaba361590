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
  HULLPOSE_THROW_UNLESS(
      s.shadow_v_min <= s.shadow_v_max,
      p.scope() << ".shadow_v_min: must not exceed shadow_v_max (" << s.shadow_v_max << ")");
  return s;
}

namespace {

using Vec4 = Sobs::Vec4;
using Block = Sobs::Block;

constexpr float kNeverMatches = 1e15f;  // padding lane: its distance to any colour is huge

using Vec4i = int32_t __attribute__((vector_size(16)));

inline Vec4 splat(float f) {
  return Vec4{f, f, f, f};
}

// The HSV cone point of a BGR pixel. Hue and chroma come from the opponent axes
// (R - (G+B)/2, sqrt(3)/2 (G - B)) — the chroma plane of the HSV hexcone (Hanbury 2003) —
// so no trigonometry per pixel; their length is max - min = S V up to the hexagon-to-circle
// factor (between sqrt(3)/2 and 1).
inline Vec4 cone(const uint8_t* bgr) {
  constexpr float k = 1.f / 255.f, half_sqrt3 = 0.8660254f;
  const float b = bgr[0] * k, g = bgr[1] * k, r = bgr[2] * k;
  return Vec4{r - 0.5f * (g + b), half_sqrt3 * (g - b), std::max(r, std::max(g, b)), 0.f};
}

inline Vec4 dist2(const Block& b, Vec4 px, Vec4 py, Vec4 pv) {
  const Vec4 dx = b.x - px, dy = b.y - py, dv = b.v - pv;
  return dx * dx + dy * dy + dv * dv;
}

inline void blend(Block& b, Vec4 w, Vec4 px, Vec4 py, Vec4 pv) {
  b.x += w * (px - b.x);
  b.y += w * (py - b.y);
  b.v += w * (pv - b.v);
}

}  // namespace

void Sobs::begin_learning(cv::Size size) {
  size_ = size;
  learnt_ = 0;
  const size_t rows = 3 * static_cast<size_t>(size.height) + 2,
               cols = static_cast<size_t>(size.width) + 2;
  map_.assign(rows * cols, Block{splat(kNeverMatches), splat(0.f), splat(0.f)});
}

void Sobs::learn(const cv::Mat& bgr) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_);
  if (learnt_ == 0) {  // the map starts as nine copies of the first frame
    const size_t cols = static_cast<size_t>(size_.width) + 2;
    for (int y = 0; y < size_.height; ++y)
      for (int x = 0; x < size_.width; ++x) {
        const Vec4 c = cone(bgr.ptr<uint8_t>(y) + 3 * x);
        for (size_t b = 0; b < 3; ++b) {
          Block& blk =
              map_[(3 * static_cast<size_t>(y) + b + 1) * cols + static_cast<size_t>(x) + 1];
          blk.x = Vec4{c[0], c[0], c[0], kNeverMatches};
          blk.y = splat(c[1]);
          blk.v = splat(c[2]);
        }
      }
  }
  ++learnt_;
  const double alpha = std::max(params_.alpha_online, params_.alpha_learn / learnt_);
  step(bgr, static_cast<float>(params_.epsilon_learn), static_cast<float>(alpha), nullptr);
}

void Sobs::end_learning() {
  HULLPOSE_THROW_UNLESS(learnt_ > 0, "sobs: no background frame was learnt");
}

void Sobs::apply(const cv::Mat& bgr, cv::Mat& mask) {
  HULLPOSE_ASSERT(bgr.type() == CV_8UC3 && bgr.size() == size_ && mask.size() == size_ &&
                  mask.type() == CV_8UC1);
  step(bgr, static_cast<float>(params_.epsilon_online), static_cast<float>(params_.alpha_online),
       &mask);
}

// One pass of the network over a frame. Written by hand: it is the method
// itself, and the per-pixel best-match search and neighbourhood update are data-dependent, which
// no OpenCV primitive expresses. Per pixel, SIMD over the three cells of a block row.
void Sobs::step(const cv::Mat& bgr, float epsilon, float alpha, cv::Mat* mask) {
  const size_t w = static_cast<size_t>(size_.width), cols = w + 2;
  // Neighbourhood weights: the 3 x 3 Gaussian (1 2 1)^T (1 2 1) / 4, so the best match moves by
  // alpha. For a best match in lane a of a block row, `own` weighs the lanes of the same block and
  // `side` the one lane of the neighbouring block (left for a = 0, right for a = 2) that falls in
  // the neighbourhood; for a = 1 `side` is all zero and points at the own block.
  const float row_w[3] = {0.5f, 1.f, 0.5f};
  Vec4 own[3][3], side[3][3];
  const std::ptrdiff_t side_offset[3] = {-1, 0, 1};
  for (int a = 0; a < 3; ++a) {
    Vec4 o = splat(0.f), s = splat(0.f);
    for (int j = 0; j < 3; ++j) o[j] = j == a ? 1.f : std::abs(j - a) == 1 ? 0.5f : 0.f;
    if (a == 0) s[2] = 0.5f;
    if (a == 2) s[0] = 0.5f;
    for (int dy = 0; dy < 3; ++dy) {
      own[a][dy] = o * splat(alpha * row_w[dy]);
      side[a][dy] = s * splat(alpha * row_w[dy]);
    }
  }
  const float v_min = static_cast<float>(params_.shadow_v_min),
              v_max = static_cast<float>(params_.shadow_v_max);
  const float s_max = static_cast<float>(params_.shadow_s_max),
              h_max = static_cast<float>(params_.shadow_h_max);
  for (int y = 0; y < size_.height; ++y) {
    uint8_t* out = mask ? mask->ptr<uint8_t>(y) : nullptr;
    const uint8_t* in = bgr.ptr<uint8_t>(y);
    Block* row0 = &map_[(3 * static_cast<size_t>(y) + 1) * cols + 1];
    for (size_t x = 0; x < w; ++x) {
      const Vec4 p = cone(in + 3 * x);
      const Vec4 px = splat(p[0]), py = splat(p[1]), pv = splat(p[2]);
      Block* r0 = row0 + x;
      const Vec4 d0 = dist2(r0[0], px, py, pv), d1 = dist2(r0[cols], px, py, pv),
                 d2 = dist2(r0[2 * cols], px, py, pv);
      // Branch-free argmin over the nine cells (the winner is data, not a predictable branch):
      // per lane the best row, then the best lane.
      const Vec4i take1 = d1 < d0;
      const Vec4 m01 = take1 ? d1 : d0;
      const Vec4i row01 = take1 ? Vec4i{1, 1, 1, 1} : Vec4i{0, 0, 0, 0};
      const Vec4i take2 = d2 < m01;
      const Vec4 m = take2 ? d2 : m01;
      const Vec4i rows = take2 ? Vec4i{2, 2, 2, 2} : row01;
      const bool l1 = m[1] < m[0];
      const float m_01 = l1 ? m[1] : m[0];
      const int a_01 = l1 ? 1 : 0;
      const bool l2 = m[2] < m_01;
      const float best = l2 ? m[2] : m_01;
      const int a = l2 ? 2 : a_01;
      const int b = l2 ? rows[2] : l1 ? rows[1] : rows[0];
      Block* centre = b == 0 ? r0 : b == 1 ? r0 + cols : r0 + 2 * cols;
      if (best <= epsilon) {
        if (out) out[x] = 0;
        for (int dy = 0; dy < 3; ++dy) {
          Block* t =
              centre + static_cast<std::ptrdiff_t>(dy - 1) * static_cast<std::ptrdiff_t>(cols);
          blend(t[0], own[a][dy], px, py, pv);
          blend(t[side_offset[a]], side[a][dy], px, py, pv);
        }
        continue;
      }
      if (!out) continue;
      // Shadow: darker than the best match by a bounded ratio, similar saturation and hue.
      const float bx = centre->x[a], by = centre->y[a], bv = centre->v[a];
      bool shadow = false;
      if (bv > 1e-3f && p[2] > 1e-3f) {
        const float ratio = p[2] / bv;
        const float cp = std::sqrt(p[0] * p[0] + p[1] * p[1]), cb = std::sqrt(bx * bx + by * by);
        const float ds = std::abs(cp / p[2] - cb / bv);
        float dh = 0.f;
        if (cp > 0.02f && cb > 0.02f) {  // hue is meaningless for greys
          dh = std::abs(std::atan2(p[1], p[0]) - std::atan2(by, bx));
          dh = std::min(dh, 2.f * std::numbers::pi_v<float> - dh);
        }
        shadow = ratio >= v_min && ratio <= v_max && ds <= s_max && dh <= h_max;
      }
      out[x] = shadow ? 0 : 255;
    }
  }
}

}  // namespace hullpose::camera_node
