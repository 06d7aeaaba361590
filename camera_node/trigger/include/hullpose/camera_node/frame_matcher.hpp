#pragma once
// Tags camera frames with the trigger sequence they belong to.
// External trigger: the sensor exposes at the edge, so the frame at that edge (within
// max_residual_us, a small exposure delay) is the one. Free-running camera: for each edge, the
// frame whose sensor timestamp is nearest to it; the residual (frame - edge) is reported so the
// fusion host and the logs can see how far off the instant is. A decision waits until a frame at
// or after the edge has been seen (no later frame can be nearer) or max_residual_us has passed.
// Each frame serves at most one edge. Frames are opaque ids (the capture stage's buffer ids).
#include <cstdint>
#include <vector>

#include "hullpose/camera_node/sequence_mapper.hpp"
#include "hullpose/common/counters.hpp"

namespace hullpose::trigger {

struct TaggedFrame {
  int64_t frame_id = 0;
  int64_t frame_us = 0;  // sensor timestamp, node clock
  MappedEdge edge;
  int64_t residual_us = 0;  // frame_us - edge.edge_us
  // Sensor timestamp on the master's clock (silhouette_t.capture_utime).
  int64_t capture_utime() const { return frame_us - edge.offset_us; }
};

struct FrameMatcherConfig {
  // External trigger: a few ms. Free-running: half the camera's frame interval.
  int64_t max_residual_us = 5'000;
  static constexpr size_t kFrames = 32;
  static constexpr size_t kEdges = 32;
};

class FrameMatcher {
 public:
  explicit FrameMatcher(const FrameMatcherConfig& config = {});
  void on_frame(int64_t frame_id, int64_t frame_us);
  void on_edge(const MappedEdge& edge);
  // Appends decided edges with their frame; edges without a frame within max_residual_us are
  // counted as "no_frame" and dropped.
  void poll(int64_t now_us, std::vector<TaggedFrame>& out);
  const Counters& counters() const { return counters_; }
  size_t pending_edges() const { return edges_.size(); }

 private:
  struct Frame {
    int64_t id, us;
    bool used;
  };
  FrameMatcherConfig config_;
  std::vector<Frame> frames_;      // oldest first, at most kFrames
  std::vector<MappedEdge> edges_;  // oldest first, at most kEdges
  Counters counters_;
};

}  // namespace hullpose::trigger
