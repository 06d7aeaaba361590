#pragma once
// The camera node's trigger stage: TRIGGER announcements + edges from an EdgeSource + the
// capture stage's frames in, frames tagged with (trigger_seq, utime, capture_utime) out.
// Single-threaded: the node's loop calls it; nothing here blocks.
#include <hullpose_msg/trigger_t.hpp>
#include <string>
#include <vector>

#include "hullpose/camera_node/edge_source.hpp"
#include "hullpose/camera_node/frame_matcher.hpp"
#include "hullpose/camera_node/sequence_mapper.hpp"

namespace hullpose::trigger {

struct ListenerConfig {
  std::string rig_id;
  // >= 0: a simulated sensor that exposes one frame at every edge, this long after it (the
  // listener feeds those frames to the matcher itself); < 0: frames come through on_frame().
  int64_t expose_after_edge_us = -1;
  MapperConfig mapper;
  FrameMatcherConfig matcher;
};

class TriggerListener {
 public:
  TriggerListener(const ListenerConfig& config, EdgeSource& edges);
  // received_us: arrival on the node clock. Announcements of other rigs are counted and ignored.
  void on_announcement(const hullpose_msg::trigger_t& msg, int64_t received_us);
  void on_frame(int64_t frame_id, int64_t frame_us) { matcher_.on_frame(frame_id, frame_us); }
  // Drains the edge source, maps edges, appends the frames that are now tagged.
  void poll(int64_t now_us, std::vector<TaggedFrame>& out);

  // No edge waiting for its announcement or its frame: nothing to do until the next edge.
  bool idle() const { return mapper_.pending_edges() == 0 && matcher_.pending_edges() == 0; }
  const SequenceMapper& mapper() const { return mapper_; }
  const FrameMatcher& matcher() const { return matcher_; }
  int64_t foreign_announcements() const { return foreign_; }

 private:
  ListenerConfig config_;
  EdgeSource& edges_;
  SequenceMapper mapper_;
  FrameMatcher matcher_;
  std::vector<MappedEdge> mapped_;
  int64_t foreign_ = 0;
  int64_t exposed_ = 0;  // frame ids of the simulated sensor
};

}  // namespace hullpose::trigger
