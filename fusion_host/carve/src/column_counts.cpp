#include "hullpose/carve/column_counts.hpp"

#include <algorithm>
#include <array>
#include <opencv2/core/hal/intrin.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::carve {

namespace {

constexpr int kLanes = 16;

size_t row_stride(int width) {
  return static_cast<size_t>((width + 2 * kLanes - 1) / kLanes * kLanes);
}

// Lanes [0, n) set, for n in 0..16: 16 - n bytes into 16 set bytes and 16 clear ones.
cv::v_uint8x16 first_lanes(int n) {
  static constexpr std::array<uint8_t, 2 * kLanes> kRamp = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff,
                                                            0xff, 0xff, 0xff, 0xff, 0xff, 0xff,
                                                            0xff, 0xff, 0xff, 0xff};
  return cv::v_load(kRamp.data() + kLanes - n);
}

}  // namespace

void ColumnCounts::reserve(int width, int height) {
  HULLPOSE_ASSERT(width > 0 && height > 0);
  above_.reserve(row_stride(width) * static_cast<size_t>(height + 1));
}

void ColumnCounts::build(const cv::Mat& mask, const cv::Rect& box) {
  HULLPOSE_ASSERT(mask.type() == CV_8UC1 &&
                  (box.area() == 0 || (box & cv::Rect(0, 0, mask.cols, mask.rows)) == box));
  box_ = box.area() > 0 ? box : cv::Rect();
  stride_ = row_stride(box_.width);
  above_.resize(stride_ * static_cast<size_t>(box_.height + 1));
  std::fill_n(above_.begin(), stride_, uint8_t{0});
  const int width = box_.width,
            readable =
                mask.cols - box_.x;  // readable: bytes of an image row from the box's left edge on
  const cv::v_uint8x16 zero = cv::v_setzero_u8();
  // Foreground lanes of the 16 pixels at box column x: 0xff = -1, so subtracting counts one.
  const auto foreground = [&](const uint8_t* row, int x) {
    cv::v_uint8x16 fg;
    if (x + kLanes <= readable) {
      fg = cv::v_load(row + x) != zero;
    } else {  // the image's last pixels: no vector load past its end
      alignas(16) std::array<uint8_t, kLanes> tail{};
      for (int i = 0; x + i < width; ++i) tail[static_cast<size_t>(i)] = row[x + i] ? 0xff : 0;
      fg = cv::v_load_aligned(tail.data());
    }
    return width - x < kLanes ? fg & first_lanes(width - x) : fg;  // the slack stays zero
  };
  // Down strips of 64 columns, the running counts in registers: row by row across the box would
  // chain every row's counts to the previous row's stores, and the strided reads of one strip
  // suit the hardware prefetcher.
  for (int xs = 0; xs < width; xs += 4 * kLanes) {
    const int chunks = std::min(4, (width - xs + kLanes - 1) / kLanes);
    cv::v_uint8x16 c0 = zero, c1 = zero, c2 = zero, c3 = zero;
    for (int y = 0; y < box_.height; ++y) {
      const uint8_t* row = mask.ptr<uint8_t>(box_.y + y) + box_.x;
      uint8_t* out = &above_[static_cast<size_t>(y + 1) * stride_ + static_cast<size_t>(xs)];
      c0 = cv::v_sub_wrap(c0, foreground(row, xs));
      cv::v_store(out, c0);
      if (chunks < 2) continue;
      c1 = cv::v_sub_wrap(c1, foreground(row, xs + kLanes));
      cv::v_store(out + kLanes, c1);
      if (chunks < 3) continue;
      c2 = cv::v_sub_wrap(c2, foreground(row, xs + 2 * kLanes));
      cv::v_store(out + 2 * kLanes, c2);
      if (chunks < 4) continue;
      c3 = cv::v_sub_wrap(c3, foreground(row, xs + 3 * kLanes));
      cv::v_store(out + 3 * kLanes, c3);
    }
  }
}

Coverage ColumnCounts::cover(int x0, int y0, int x1, int y1) const {
  // Box coordinates, clipped to the box: what lies outside it is background.
  const int cx0 = std::max(x0, box_.x) - box_.x, cy0 = std::max(y0, box_.y) - box_.y;
  const int cx1 = std::min(x1, box_.x + box_.width - 1) - box_.x;
  const int cy1 = std::min(y1, box_.y + box_.height - 1) - box_.y;
  if (cx0 > cx1 || cy0 > cy1) return Coverage::kNone;
  const bool clipped =
      cx0 + box_.x != x0 || cy0 + box_.y != y0 || cx1 + box_.x != x1 || cy1 + box_.y != y1;
  const int rows = cy1 - cy0 + 1;
  if (rows > 255) {
    // Counts modulo 256 cannot tell 0 from 256 here: only "no foreground" is certain, and only
    // if every row segment of 255 rows says so.
    for (int y = cy0; y <= cy1; y += 255)
      if (cover(x0, y + box_.y, x1, std::min(y + 254, cy1) + box_.y) != Coverage::kNone)
        return Coverage::kSome;
    return Coverage::kNone;
  }
  const uint8_t* top = &above_[static_cast<size_t>(cy0) * stride_];
  const uint8_t* bottom = &above_[static_cast<size_t>(cy1 + 1) * stride_];
  const cv::v_uint8x16 zero = cv::v_setzero_u8(),
                       height = cv::v_setall_u8(static_cast<uint8_t>(rows));
  bool any = false, all = !clipped;
  for (int x = cx0; x <= cx1; x += kLanes) {
    const cv::v_uint8x16 count = cv::v_sub_wrap(cv::v_load(bottom + x), cv::v_load(top + x));
    const int valid = cx1 - x + 1 >= kLanes ? 0xffff : (1 << (cx1 - x + 1)) - 1;
    any = any || (cv::v_signmask(count == zero) & valid) != valid;
    all = all && (cv::v_signmask(count == height) & valid) == valid;
    if (any && !all) return Coverage::kSome;
  }
  return !any ? Coverage::kNone : all ? Coverage::kAll : Coverage::kSome;
}

}  // namespace hullpose::carve
