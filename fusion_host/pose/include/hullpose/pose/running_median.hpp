#pragma once
// Median of the last N values, in fixed buffers (no allocation): the pose stage's running
// stature and running hull score.
#include <algorithm>
#include <array>

namespace hullpose::pose {

template <int N>
class RunningMedian {
 public:
  // Adds `value` and returns the median of the window including it.
  double add(double value) {
    ring_[next_] = value;
    next_ = (next_ + 1) % N;
    count_ = std::min(count_ + 1, N);
    std::copy_n(ring_.begin(), count_, scratch_.begin());
    const auto mid = scratch_.begin() + count_ / 2;
    std::nth_element(scratch_.begin(), mid, scratch_.begin() + count_);
    return *mid;
  }
  int count() const { return count_; }
  void reset() { count_ = next_ = 0; }

 private:
  std::array<double, N> ring_{}, scratch_{};
  int count_ = 0, next_ = 0;
};

}  // namespace hullpose::pose
