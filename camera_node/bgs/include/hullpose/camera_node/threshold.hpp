#pragma once
// Not a background model: foreground wherever the grey level reaches `level` (default 128). For
// sources whose frames are segmented already (a replayed mask dataset, a keyed or IR camera),
// so that the node publishes exactly the masks it is given. It learns nothing.
#include "hullpose/camera_node/background_subtractor.hpp"

namespace hullpose::camera_node {

class ThresholdSubtractor final : public BackgroundSubtractor {
 public:
  explicit ThresholdSubtractor(const Params& params);
  std::string_view name() const override { return "threshold"; }
  void begin_learning(cv::Size size) override;
  void learn(const cv::Mat&) override {}
  void end_learning() override {}
  void apply(const cv::Mat& bgr, cv::Mat& mask) override;

 private:
  int level_;
  cv::Mat grey_;
};

}  // namespace hullpose::camera_node
