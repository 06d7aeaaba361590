#pragma once
// Replays an image sequence (a printf pattern such as cam3/rgb_%06d.png, read from first_index
// until a file is missing) or a video file (OpenCV videoio). Frame f gets capture_utime =
// start_utime + f * 1e6 / fps. Triggered (expose()), the frame is the trigger's sequence number
// (modulo the length when looping) and the trigger stage's capture time.
//
// Parameters: path (required), fps (30), start_utime (0: the time start() was called),
// first_index (0), loop (false), preload (false: read every frame into memory at start(), so that
// grab() neither allocates nor touches the disk — for benchmarks and tests; without it each frame
// is decoded from disk, which allocates).
// A frame that does not decode (a corrupt image file, a damaged or truncated video) is
// GrabStatus::kCorruptFrame, logged: that camera is missing for that frame, the next is read.
#include <opencv2/videoio.hpp>

#include "hullpose/camera_node/frame_source.hpp"

namespace hullpose::camera_node {

class FileSource final : public FrameSource {
 public:
  FileSource(const Params& params, const SourceContext& context);
  void start() override;
  GrabStatus grab(Frame& frame, int timeout_ms) override;
  void stop() override;
  std::string describe() const override;
  bool triggerable() const override { return true; }
  void expose(int64_t trigger_seq, int64_t capture_utime) override;
  void prepare(int64_t trigger_seq) override;

 private:
  enum class Read { kFrame, kEnd, kCorrupt };
  Read read_next(cv::Mat& out);
  void seek(int index);
  int64_t frame_of(int64_t trigger_seq) const;
  std::string path_;
  bool pattern_ = false;
  std::string prefix_, suffix_;  // an image sequence's path around the index ...
  int width_ = 0;                // ... and the index's zero-padded width
  double fps_ = 30;
  int64_t start_utime_ = 0;
  int first_index_ = 0;
  bool loop_ = false;
  bool preload_ = false;
  cv::Size size_;
  int camera_id_ = 0;

  cv::VideoCapture video_;
  std::vector<cv::Mat> frames_;  // preloaded
  int next_index_ = 0;
  int count_ = -1;  // frames in the sequence or video, -1 if unknown
  int64_t exposed_index_ = -1, exposed_utime_ = 0;
  int64_t delivered_ = 0;
  int64_t t0_ = 0;
  cv::Mat image_;
  cv::Mat prepared_;  // an image sequence's frame prepared_index_, decoded ahead
  int prepared_index_ = -1;
  int64_t corrupt_ = 0;
};

}  // namespace hullpose::camera_node
