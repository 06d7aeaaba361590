#pragma once
// Small rigs and messages for the rig tests.
#include <hullpose_msg/silhouette_t.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "hullpose/common/rig.hpp"
#include "hullpose/common/silhouette_codec.hpp"

namespace hullpose::testing {

// n cameras on a circle looking at the origin, each w x h pixels.
inline Rig make_rig(int n, int w = 64, int h = 48, const std::string& id = "rigA") {
  Rig rig;
  rig.rig_id = id;
  rig.volume.min_mm = {-1000, -1000, 0};
  rig.volume.max_mm = {1000, 1000, 2000};
  for (int i = 0; i < n; ++i) {
    CameraModel c;
    c.id = i;
    c.name = "cam" + std::to_string(i);
    c.width = w;
    c.height = h;
    c.fx = c.fy = 50;
    c.cx = w / 2.0;
    c.cy = h / 2.0;
    c.t = {0, 0, 3000};
    rig.cameras.push_back(c);
  }
  rig.validate();
  return rig;
}

// A silhouette message for camera `cam` at trigger `seq`, with a disc at a seq-dependent place.
inline hullpose_msg::silhouette_t make_silhouette(const Rig& rig, int cam, int64_t seq,
                                                  int64_t utime) {
  const CameraModel& c = *rig.find(cam);
  cv::Mat mask(c.height, c.width, CV_8UC1, cv::Scalar(0));
  cv::circle(mask, {static_cast<int>(5 + seq % (c.width - 10)), c.height / 2}, 4, cv::Scalar(255),
             -1);
  hullpose_msg::silhouette_t m{};
  m.utime = utime;
  m.rig_id = rig.rig_id;
  m.camera_id = cam;
  m.trigger_seq = seq;
  m.capture_utime = utime + 300;
  m.width = c.width;
  m.height = c.height;
  const PixelRoi roi = SilhouetteEncoder().encode(mask, m.payload);
  m.roi_x = roi.x;
  m.roi_y = roi.y;
  m.roi_width = roi.width;
  m.roi_height = roi.height;
  m.encoding = hullpose_msg::silhouette_t::ENCODING_RLE_V1;
  m.payload_size = static_cast<int32_t>(m.payload.size());
  m.node_done_utime = utime + 5000;
  return m;
}

template <typename Msg>
std::vector<uint8_t> encode(const Msg& m) {
  std::vector<uint8_t> buf(static_cast<size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

}  // namespace hullpose::testing
