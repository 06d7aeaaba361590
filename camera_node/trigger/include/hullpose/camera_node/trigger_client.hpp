#pragma once
// The trigger stage as a camera node's capture loop uses it with an externally triggered
// camera: it owns the TRIGGER subscription and the edge source, and tags each frame as it comes
// (camera_node's FrameStamper seam):
//
//   auto edges = open_edge_source("gpiod:gpiochip0:17", clock);
//   TriggerClient client(bus, *edges, listener_config, clock);   // the process's bus
//   stamper = [&](const Frame& f) { auto t = client.tag(f.sequence, f.capture_utime, 20); ... };
//
// A simulated sensor (ListenerConfig::expose_after_edge_us >= 0) exposes at every edge by itself:
// next_exposure() hands out its frames, tagged, one per edge, and the source then renders them.
// A client serves one kind of camera: use tag() or next_exposure(), not both.
// A free-running camera needs the frames after an edge to choose the nearest one: offer() each
// frame, keep the last few, and publish the ones it hands back.
#include <optional>
#include <vector>

#include "hullpose/camera_node/trigger_listener.hpp"
#include "hullpose/common/bus.hpp"

namespace hullpose::trigger {

class TriggerClient {
 public:
  // Times come from `clock` (tests: NodeClock on a SimClock); waiting is real (poll()).
  TriggerClient(bus::Bus& bus, EdgeSource& edges, const ListenerConfig& config,
                const NodeClock& clock, const std::string& channel = "TRIGGER");
  ~TriggerClient();
  TriggerClient(const TriggerClient&) = delete;
  TriggerClient& operator=(const TriggerClient&) = delete;

  // Tags one frame: frame_utime is its sensor timestamp, microseconds since the epoch on this
  // node's realtime clock. Handles TRIGGER messages and edges until the frame's edge is mapped
  // or wait_ms passes; std::nullopt if it belongs to no trigger edge (counted).
  std::optional<TaggedFrame> tag(int64_t frame_id, int64_t frame_utime, int wait_ms);
  // Free-running camera: hands the frame to the matcher and returns at once with every frame
  // (this one or earlier) now chosen as the nearest to an edge, oldest edge first. A frame is
  // decided once a later frame has been seen or max_residual_us has passed, so the caller keeps
  // the last few frames until then.
  void offer(int64_t frame_id, int64_t frame_utime, std::vector<TaggedFrame>& decided);
  // Simulated sensor: the next frame it exposed, tagged (frame_us on the node clock), oldest
  // first; at most kSensorBuffers wait, older ones are dropped, counted "overrun". Handles
  // TRIGGER messages and edges for up to wait_ms; std::nullopt if none is tagged by then.
  static constexpr size_t kSensorBuffers = 4;
  std::optional<TaggedFrame> next_exposure(int wait_ms);

  const TriggerListener& listener() const { return listener_; }
  const Counters& counters() const { return counters_; }

 private:
  int64_t to_node_clock(int64_t frame_utime) const;
  // Handles what is pending on the bus and the trigger input, then waits for either, until
  // `done` (which sees the newly tagged frames) says so or wait_ms passes.
  template <class Done>
  bool pump(int wait_ms, Done&& done);

  bus::Bus& bus_;
  EdgeSource& edges_;
  NodeClock clock_;
  TriggerListener listener_;
  bus::Subscription subscription_;
  hullpose_msg::trigger_t msg_;
  std::vector<TaggedFrame> tagged_;
  size_t next_tagged_ = 0;  // next_exposure(): tagged_[next_tagged_..] wait to be handed out
  Counters counters_;
};

}  // namespace hullpose::trigger
