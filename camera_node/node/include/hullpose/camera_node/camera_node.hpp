#pragma once
// One camera node: frame source -> background subtraction (in the ROI) -> clean-up -> silhouette
// published on LCM, stamped with the trigger instant the frame belongs to.
//
// Lifecycle:
//
//   auto bus = open_node_bus(config);            // the process's one bus (lcm.url)
//   CameraNode node(config, *bus);             // validates everything; opens nothing
//   node.start();                              // opens the camera, learns the background, then
//                                              // opens the trigger input (config trigger:)
//   node.run(stop_flag);                       // capture -> trigger stamp -> process, until
//   stopped node.stop();
//
// The trigger layer (camera_node/trigger, through TriggerStage) sits behind FrameTrigger: a camera
// that exposes on the trigger line has each frame stamped with its edge (stamp()); a simulated
// sensor (FrameSource::triggerable) waits for the next trigger instant (next_instant()) and
// exposes that instant's frame, exactly one per edge; a free-running camera (trigger.camera:
// free_running) keeps its last few frames and publishes the one nearest each edge (offer()).
// Without a trigger the node is free-running: trigger_seq = frame.sequence, trigger utime =
// frame.capture_utime. A frame without a trigger instant is dropped, counted "no_trigger".
//
// One step at a time, as run() does it: node.capture(frame, timeout_ms); node.process(frame,
// stamp). capture() and process() must be called from one thread (the capture thread). Statistics
// go on the STATUS channel every lcm.status_period_ms and once more at stop().
#include <array>
#include <atomic>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hullpose/camera_node/background_subtractor.hpp"
#include "hullpose/camera_node/frame_source.hpp"
#include "hullpose/camera_node/mask_cleanup.hpp"
#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/camera_node/publisher.hpp"
#include "hullpose/common/bus.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::camera_node {

struct TriggerStamp {
  int64_t seq = 0;    // trigger sequence number announced by firmware_sync
  int64_t utime = 0;  // the trigger edge, microseconds since the epoch (master clock)
  // This node's realtime clock minus the master's: frame and node times are sent on the master's
  // clock (silhouette_t capture_utime, node_done_utime). 0 without a trigger.
  int64_t clock_offset_us = 0;
  // next_instant(): when the simulated sensor exposes, microseconds since the epoch (node clock).
  int64_t capture_utime = 0;
};

// The trigger layer as the capture loop sees it (implemented by TriggerStage).
class FrameTrigger {
 public:
  virtual ~FrameTrigger() = default;
  // Opens the trigger input; throws hullpose::Error naming the device when it is absent.
  virtual void start() = 0;
  // A camera exposing on the trigger line: the trigger instant of `frame`, std::nullopt if none.
  virtual std::optional<TriggerStamp> stamp(const Frame& frame) = 0;
  // A simulated sensor: the next trigger instant, waiting up to timeout_ms; std::nullopt if none.
  virtual std::optional<TriggerStamp> next_instant(int timeout_ms) = 0;
  // A free-running camera (config trigger.camera: free_running): takes `frame` and returns at
  // once, in `decided`, the frames (by Frame::sequence, this one or earlier) now chosen as nearest
  // to a trigger edge, with that edge's stamp.
  virtual void offer(const Frame& frame,
                     std::vector<std::pair<int64_t, TriggerStamp>>& decided) = 0;
  // Counters and state for STATUS and the log (mapping drops, clock offset).
  virtual void report(std::vector<std::pair<std::string, int64_t>>& out) const = 0;
};

// The bus at the config's lcm.url; throws hullpose::Error naming the file and lcm.url.
std::unique_ptr<bus::Bus> open_node_bus(const NodeConfig& config);

class CameraNode {
 public:
  // Loads the rig, checks the camera id, the ROI and every stage's parameters. Publishes and
  // hears TRIGGER on `bus` (the process's, which outlives the node). Throws hullpose::Error
  // naming the config file and field. `trigger` replaces the one the config's trigger: section
  // describes (tests inject simulated edges this way).
  CameraNode(NodeConfig config, bus::Bus& bus,
             const SourceRegistry& sources = SourceRegistry::builtin(),
             std::unique_ptr<FrameTrigger> trigger = nullptr);
  ~CameraNode();
  CameraNode(const CameraNode&) = delete;
  CameraNode& operator=(const CameraNode&) = delete;

  // Opens the source (throws naming the device and what was tried), learns the background from
  // bgs.learn_frames frames (of bgs.background if set, else the source's first frames), then
  // opens the trigger input (throws naming the GPIO chip and line, or the wire).
  void start();
  // The next frame of the source; records the time spent waiting as the capture time.
  GrabStatus capture(Frame& frame, int timeout_ms);
  // Subtracts, cleans up, encodes and queues the silhouette of `frame` stamped with `stamp`.
  // Returns the published mask (full image, 255 = person), valid until the next call.
  const cv::Mat& process(const Frame& frame, const TriggerStamp& stamp);
  // capture -> trigger stamp -> process until stop_requested or the end of a finite source.
  void run(const std::atomic<bool>& stop_requested);
  // Stops the source, sends what is queued and a final STATUS. Safe to call twice.
  void stop();

  const NodeConfig& config() const { return config_; }
  const Rig& rig() const { return rig_; }
  Counters& counters() { return counters_; }
  int64_t frames_processed() const { return frames_total_; }

 private:
  void learn_background();
  void run_free_running(const std::atomic<bool>& stop_requested);
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
  std::unique_ptr<FrameTrigger> trigger_;
  cv::Mat mask_, roi_mask_;
  // Free-running camera: the last frames, until the trigger layer has chosen among them.
  static constexpr size_t kHeldFrames = 4;
  std::array<Frame, kHeldFrames> held_;
  std::vector<std::pair<int64_t, TriggerStamp>> decided_;
  bool started_ = false;
  int32_t last_capture_us_ = 0;

  // Statistics of the current STATUS interval.
  int64_t frames_total_ = 0, last_trigger_seq_ = -1;
  int64_t interval_start_us_ = 0, interval_frames_ = 0;
  int64_t sum_capture_us_ = 0, sum_subtract_us_ = 0, sum_morphology_us_ = 0, sum_encode_us_ = 0;
};

}  // namespace hullpose::camera_node
