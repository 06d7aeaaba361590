#include "hullpose/camera_node/mask_cleanup.hpp"

#include <opencv2/imgproc.hpp>

namespace hullpose::camera_node {

MaskCleanup::MaskCleanup(CleanupParams params) : params_(params) {
  const auto disc = [](int r) {
    return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  };
  if (params_.open_radius > 0) open_kernel_ = disc(params_.open_radius);
  if (params_.close_radius > 0) close_kernel_ = disc(params_.close_radius);
}

void MaskCleanup::apply(cv::Mat& mask) {
  if (!open_kernel_.empty()) {
    cv::erode(mask, tmp_, open_kernel_);
    cv::dilate(tmp_, mask, open_kernel_);
  }
  if (!close_kernel_.empty()) {
    cv::dilate(mask, tmp_, close_kernel_);
    cv::erode(tmp_, mask, close_kernel_);
  }
  if (params_.min_blob_area <= 0) return;
  // Plain labelling plus our own area count: connectedComponentsWithStats computes bounding
  // boxes and centroids per pixel too and costs ~10x the labelling (6.5 vs 0.55 ms at 800x600,
  // OpenCV 4.6, one thread); only the area is needed here.
  const int n = cv::connectedComponents(mask, labels_, 8, CV_32S);
  area_.assign(static_cast<size_t>(n), 0);  // grows to the largest count seen, then stays
  for (int y = 0; y < labels_.rows; ++y) {
    const int32_t* lab = labels_.ptr<int32_t>(y);
    for (int x = 0; x < labels_.cols; ++x) ++area_[static_cast<size_t>(lab[x])];
  }
  if (keep_.size() < static_cast<size_t>(n)) keep_.resize(static_cast<size_t>(n));
  bool any_removed = false;
  keep_[0] = 0;
  for (size_t i = 1; i < static_cast<size_t>(n); ++i) {
    keep_[i] = area_[i] >= params_.min_blob_area ? 255 : 0;
    any_removed = any_removed || keep_[i] == 0;
  }
  if (!any_removed) return;
  for (int y = 0; y < mask.rows; ++y) {
    const int32_t* lab = labels_.ptr<int32_t>(y);
    uint8_t* m = mask.ptr<uint8_t>(y);
    for (int x = 0; x < mask.cols; ++x) m[x] = keep_[static_cast<size_t>(lab[x])];
  }
}

}  // namespace hullpose::camera_node
