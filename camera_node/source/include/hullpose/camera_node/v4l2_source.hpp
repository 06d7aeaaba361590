#pragma once
// Video4Linux2 capture with mmap streaming. Parameters: device (/dev/video0), pixel_format
// (YUYV | BGR3 | RGB3 | GREY; default YUYV), buffers (4). The image size is the rig camera's.
// Timestamps come from the driver's buffer timestamps (CLOCK_MONOTONIC), mapped to the epoch.
#include <cstdint>
#include <vector>

#include "hullpose/camera_node/frame_source.hpp"

namespace hullpose::camera_node {

class V4l2Source final : public FrameSource {
 public:
  V4l2Source(const Params& params, const SourceContext& context);
  ~V4l2Source() override;
  void start() override;
  GrabStatus grab(Frame& frame, int timeout_ms) override;
  void stop() override;
  std::string describe() const override;

 private:
  struct Buffer {
    void* data = nullptr;
    size_t length = 0;
  };
  std::string device_;
  uint32_t fourcc_ = 0;
  int buffer_count_ = 4;
  cv::Size size_;
  int camera_id_ = 0;
  int fd_ = -1;
  uint32_t stride_ = 0;
  std::vector<Buffer> buffers_;
  bool streaming_ = false;
  int64_t first_sequence_ = -1;
  cv::Mat image_;
};

}  // namespace hullpose::camera_node
