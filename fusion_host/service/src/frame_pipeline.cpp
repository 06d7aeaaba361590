#include "hullpose/fusion_host/frame_pipeline.hpp"

namespace hullpose::fusion {

void views_by_camera_index(const AssembledFrame& frame, size_t num_cameras,
                           std::vector<cv::Mat>& masks, std::vector<PixelRoi>& rois) {
  masks.resize(num_cameras);
  rois.resize(num_cameras);
  for (auto& m : masks) m.release();
  for (auto& r : rois) r = {};
  for (const View& v : frame.views) {
    const auto i = static_cast<size_t>(v.camera_index);
    if (i >= num_cameras) continue;
    masks[i] = *v.mask;
    rois[i] = v.roi;
  }
}

}  // namespace hullpose::fusion
