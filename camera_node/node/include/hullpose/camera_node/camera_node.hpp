#pragma once
// One camera node: frame source -> background subtraction (in the ROI) -> clean-up -> silhouette
// published on LCM, stamped with the trigger instant the frame belongs to.
//
// Lifecycle and the seam for the trigger layer (camera_node/trigger):
//
//   CameraNode node(load_node_config(file));   // validates everything; opens nothing
//   node.start();                              // opens the camera, learns the background
//   Frame frame;
//   while (...) {
//     if (node.capture(frame, timeout_ms) != GrabStatus::kFrame) ...;
//     TriggerStamp stamp = <match frame.capture_utime / frame.sequence to a TRIGGER announcement>;
//     node.process(frame, stamp);              // never blocks on the network
//   }
//   node.stop();
//
// or, equivalently, node.run(stop_flag, stamper) with a FrameStamper that maps a frame to its
// trigger instant (or std::nullopt to drop it, counted "no_trigger"). Without a stamper the node
// is free-running: trigger_seq = frame.sequence, trigger utime = frame.capture_utime.
//
// capture() and process() must be called from one thread (the capture thread). Statistics go on
// the STATUS channel every lcm.status_period_ms and once more at stop().
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <opencv2/core/mat.hpp>

#include "hullpose/camera_node/background_subtractor.hpp"
#include "hullpose/camera_node/frame_source.hpp"
#include "hullpose/camera_node/mask_cleanup.hpp"
#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/camera_node/publisher.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::camera_node {

struct TriggerStamp {
  int64_t seq = 0;    // trigger sequence number announced by firmware_sync
  int64_t utime = 0;  // the trigger edge, microseconds since the epoch (master clock)
};

using FrameStamper = std::function<std::optional<TriggerStamp>(const Frame&)>;

class CameraNode {
 public:
  // Loads the rig, checks the camera id, the ROI and every stage's parameters, opens LCM.
  // Throws hullpose::Error naming the config file and field.
  explicit CameraNode(NodeConfig config, const SourceRegistry& sources = SourceRegistry::builtin());
  ~CameraNode();
  CameraNode(const CameraNode&) = delete;
  CameraNode& operator=(const CameraNode&) = delete;

  // Opens the source (throws naming the device and what was tried) and learns the background
  // from bgs.learn_frames frames: of bgs.background if set, else the source's first frames.
  void start();
  // The next frame of the source; records the time spent waiting as the capture time.
  GrabStatus capture(Frame& frame, int timeout_ms);
  // Subtracts, cleans up, encodes and queues the silhouette of `frame` stamped with `stamp`.
  // Returns the published mask (full image, 255 = person), valid until the next call.
  const cv::Mat& process(const Frame& frame, const TriggerStamp& stamp);
  // capture -> stamp -> process until stop_requested or the end of a finite source.
  void run(const std::atomic<bool>& stop_requested, const FrameStamper& stamper = {});
  // Stops the source, sends what is queued and a final STATUS. Safe to call twice.
  void stop();

  const NodeConfig& config() const { return config_; }
  const Rig& rig() const { return rig_; }
  Counters& counters() { return counters_; }
  int64_t frames_processed() const { return frames_total_; }

 private:
  void learn_background();
  void maybe_publish_status(bool force, int8_t state, const std::string& message);

  NodeConfig config_;
  Rig rig_;
  CameraModel camera_;
  cv::Rect roi_;
  Counters counters_;
  std::unique_ptr<FrameSource> source_;
  std::unique_ptr<FrameSource> background_source_;
  std::unique_ptr<BackgroundSubtractor> subtractor_;
  MaskCleanup cleanup_;
  std::unique_ptr<SilhouettePublisher> publisher_;
  cv::Mat mask_, roi_mask_;
  bool started_ = false;
  int32_t last_capture_us_ = 0;

  // Statistics of the current STATUS interval.
  int64_t frames_total_ = 0, last_trigger_seq_ = -1;
  int64_t interval_start_us_ = 0, interval_frames_ = 0;
  int64_t sum_capture_us_ = 0, sum_subtract_us_ = 0, sum_morphology_us_ = 0, sum_encode_us_ = 0;
};

}  // namespace hullpose::camera_node
