#pragma once
// Background subtraction: one method per class behind one interface, chosen by name in the
// node's config (bgs.method) and built with its own parameters (bgs.params).
//
// Lifecycle:  begin_learning(size) -> learn(frame) x N -> end_learning() -> apply(frame, mask)...
// Learning may allocate; apply() must not allocate at steady state (the model and scratch
// buffers are sized in begin_learning/end_learning and reused).
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "hullpose/camera_node/params.hpp"

namespace hullpose::camera_node {

class BackgroundSubtractor {
 public:
  virtual ~BackgroundSubtractor() = default;
  virtual std::string_view name() const = 0;

  // Starts a new background model for CV_8UC3 (BGR) images of this size.
  virtual void begin_learning(cv::Size size) = 0;
  // Adds one frame of the empty scene.
  virtual void learn(const cv::Mat& bgr) = 0;
  // Builds the model from the frames seen (thresholds, codebooks, ...). Throws hullpose::Error
  // if no frame was learnt.
  virtual void end_learning() = 0;
  // Classifies one frame: mask (CV_8UC1, same size, allocated by the caller) gets 255 for
  // foreground and 0 for background, shadow and highlight.
  virtual void apply(const cv::Mat& bgr, cv::Mat& mask) = 0;
};

// Builds the method named `method` (horprasert, codebook, sobs, mog2, knn) from its parameters;
// throws hullpose::Error naming the field for an unknown method or a bad or unknown parameter.
std::unique_ptr<BackgroundSubtractor> make_subtractor(const std::string& method,
                                                      const Params& params);
std::vector<std::string> subtractor_names();

}  // namespace hullpose::camera_node
