#include "hullpose/camera_node/threshold.hpp"

#include <opencv2/imgproc.hpp>

namespace hullpose::camera_node {

ThresholdSubtractor::ThresholdSubtractor(const Params& params)
    : level_(params.get_int("level", 128, 1, 255)) {
  params.expect_all_used();
}

void ThresholdSubtractor::begin_learning(cv::Size size) {
  grey_.create(size, CV_8UC1);
}

void ThresholdSubtractor::apply(const cv::Mat& bgr, cv::Mat& mask) {
  cv::cvtColor(bgr, grey_, cv::COLOR_BGR2GRAY);
  cv::threshold(grey_, mask, level_ - 1, 255, cv::THRESH_BINARY);
}

}  // namespace hullpose::camera_node
