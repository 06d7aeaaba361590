#pragma once
// Test masks that carry their trigger sequence: a moving disc plus the low 16 bits of the
// sequence as a row of squares, so the end-to-end tests can prove that a fused frame's views
// all belong to its own sequence (frames never mixed).
#include <cstdint>
#include <opencv2/imgproc.hpp>

namespace hullpose::testing {

inline constexpr int kPatternBits = 16;

inline void draw_seq_mask(cv::Mat& mask, int64_t seq, int camera_id) {
  mask.setTo(0);
  const int w = mask.cols, h = mask.rows;
  const int x = w / 4 + static_cast<int>((seq * 3 + camera_id * 7) % (w / 2));
  cv::ellipse(mask, {x, h * 3 / 5}, {w / 12, h / 4}, 0, 0, 360, cv::Scalar(255), -1);
  for (int b = 0; b < kPatternBits; ++b)
    if ((seq >> b) & 1) mask(cv::Rect(2 + 5 * b, 2, 4, 4)).setTo(255);
}

// The sequence bits read back from a mask drawn by draw_seq_mask (full image).
inline int64_t read_seq_mask(const cv::Mat& mask) {
  int64_t seq = 0;
  for (int b = 0; b < kPatternBits; ++b)
    if (mask.at<uint8_t>(3, 3 + 5 * b) != 0) seq |= int64_t{1} << b;
  return seq;
}

}  // namespace hullpose::testing
