#pragma once
// Pixel counts of a foreground mask against ground truth: precision, recall, F1 (thesis paper 2).
#include <cstdint>
#include <opencv2/core.hpp>

namespace hullpose::test {

struct Score {
  int64_t tp = 0, fp = 0, fn = 0;
  void add(const cv::Mat& mask, const cv::Mat& truth) {
    const cv::Mat m = mask != 0, t = truth != 0;
    tp += cv::countNonZero(m & t);
    fp += cv::countNonZero(m & ~t);
    fn += cv::countNonZero(~m & t);
  }
  double precision() const {
    return tp + fp ? static_cast<double>(tp) / static_cast<double>(tp + fp) : 1.0;
  }
  double recall() const {
    return tp + fn ? static_cast<double>(tp) / static_cast<double>(tp + fn) : 1.0;
  }
  double f1() const {
    const double p = precision(), r = recall();
    return p + r > 0 ? 2 * p * r / (p + r) : 0.0;
  }
};

}  // namespace hullpose::test
