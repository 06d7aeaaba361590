#pragma once
// Morphological clean-up of a raw foreground mask (OpenCV): opening removes speckle, closing
// fills pinholes, then connected components smaller than min_blob_area are erased.
// Buffers are kept between frames.
#include <opencv2/core/mat.hpp>
#include <vector>

namespace hullpose::camera_node {

struct CleanupParams {
  int open_radius = 1;
  int close_radius = 1;
  int min_blob_area = 32;
};

class MaskCleanup {
 public:
  explicit MaskCleanup(CleanupParams params);
  // In place; mask is CV_8UC1 with 0/255.
  void apply(cv::Mat& mask);

 private:
  CleanupParams params_;
  cv::Mat open_kernel_, close_kernel_;
  cv::Mat tmp_, labels_;
  std::vector<int> area_;
  std::vector<uint8_t> keep_;
};

}  // namespace hullpose::camera_node
