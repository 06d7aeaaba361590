#pragma once
// OpenCV's MOG2 (Zivkovic 2004/2006) and KNN (Zivkovic & van der Heijden 2006) as baselines.
// Their shadow detection is on; shadow pixels (127) count as background.
#include <opencv2/video/background_segm.hpp>

#include "hullpose/camera_node/background_subtractor.hpp"

namespace hullpose::camera_node {

class OpenCvSubtractor final : public BackgroundSubtractor {
 public:
  enum class Kind { kMog2, kKnn };
  OpenCvSubtractor(Kind kind, const Params& params);
  std::string_view name() const override { return kind_ == Kind::kMog2 ? "mog2" : "knn"; }
  void begin_learning(cv::Size size) override;
  void learn(const cv::Mat& bgr) override;
  void end_learning() override;
  void apply(const cv::Mat& bgr, cv::Mat& mask) override;

 private:
  Kind kind_;
  int history_;
  double threshold_;
  double learning_rate_;
  cv::Ptr<cv::BackgroundSubtractor> impl_;
  cv::Mat scratch_;
  int learnt_ = 0;
};

}  // namespace hullpose::camera_node
