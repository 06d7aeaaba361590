#include "hullpose/camera_node/mask_cleanup.hpp"

#include <algorithm>
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
  if (params_.min_blob_area > 0) remove_small_blobs(mask);
  if (params_.max_hole_area > 0) fill_small_holes(mask);
}

void MaskCleanup::remove_small_blobs(cv::Mat& mask) {
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

void MaskCleanup::fill_small_holes(cv::Mat& mask) {
  // Only inside the foreground's bounding box: outside it all is background and connected to
  // the border, so a background region that reaches the box's edge is not a hole.
  const cv::Rect box = cv::boundingRect(mask);
  if (box.width < 3 || box.height < 3) return;
  tmp_.create(mask.size(), CV_8UC1);
  labels_.create(mask.size(), CV_32S);
  cv::Mat background = tmp_(box), labels = labels_(box), inside = mask(box);
  cv::compare(inside, 0, background, cv::CMP_EQ);
  const int n = cv::connectedComponents(background, labels, 4,
                                        CV_32S);  // written in place: same size and type
  area_.assign(static_cast<size_t>(n), 0);
  for (int y = 0; y < labels.rows; ++y) {
    const int32_t* lab = labels.ptr<int32_t>(y);
    for (int x = 0; x < labels.cols; ++x) ++area_[static_cast<size_t>(lab[x])];
  }
  if (keep_.size() < static_cast<size_t>(n)) keep_.resize(static_cast<size_t>(n));
  std::fill_n(keep_.begin(), n, uint8_t{0});  // 255: fill this region
  for (size_t i = 1; i < static_cast<size_t>(n); ++i)
    keep_[i] = area_[i] <= params_.max_hole_area ? 255 : 0;
  const auto open_to_border = [&](int x, int y) {
    keep_[static_cast<size_t>(labels.at<int32_t>(y, x))] = 0;
  };
  for (int x = 0; x < labels.cols; ++x) {
    open_to_border(x, 0);
    open_to_border(x, labels.rows - 1);
  }
  for (int y = 0; y < labels.rows; ++y) {
    open_to_border(0, y);
    open_to_border(labels.cols - 1, y);
  }
  for (int y = 0; y < labels.rows; ++y) {
    const int32_t* lab = labels.ptr<int32_t>(y);
    uint8_t* m = inside.ptr<uint8_t>(y);
    for (int x = 0; x < labels.cols; ++x) m[x] |= keep_[static_cast<size_t>(lab[x])];
  }
}

}  // namespace hullpose::camera_node
