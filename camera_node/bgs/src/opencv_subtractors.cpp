#include "hullpose/camera_node/opencv_subtractors.hpp"

#include <opencv2/imgproc.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::camera_node {

OpenCvSubtractor::OpenCvSubtractor(Kind kind, const Params& params) : kind_(kind) {
  history_ = params.get_int("history", 500, 1, 100000);
  // MOG2: squared Mahalanobis distance (OpenCV default 16); KNN: squared distance (default 400).
  threshold_ = params.get_double("threshold", kind == Kind::kMog2 ? 16.0 : 400.0, 0.01, 1e6);
  learning_rate_ =
      params.get_double("learning_rate", -1.0, -1.0, 1.0);  // -1: OpenCV's automatic rate
  params.expect_all_used();
}

void OpenCvSubtractor::begin_learning(cv::Size size) {
  if (kind_ == Kind::kMog2)
    impl_ = cv::createBackgroundSubtractorMOG2(history_, threshold_, /*detectShadows=*/true);
  else
    impl_ = cv::createBackgroundSubtractorKNN(history_, threshold_, /*detectShadows=*/true);
  scratch_.create(size, CV_8UC1);
  learnt_ = 0;
}

void OpenCvSubtractor::learn(const cv::Mat& bgr) {
  impl_->apply(bgr, scratch_, -1.0);
  ++learnt_;
}

void OpenCvSubtractor::end_learning() {
  HULLPOSE_THROW_UNLESS(learnt_ > 0, name() << ": no background frame was learnt");
}

void OpenCvSubtractor::apply(const cv::Mat& bgr, cv::Mat& mask) {
  impl_->apply(bgr, mask, learning_rate_);
  cv::threshold(mask, mask, 200, 255, cv::THRESH_BINARY);  // shadows (127) are background
}

}  // namespace hullpose::camera_node
