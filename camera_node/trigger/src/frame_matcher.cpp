#include "hullpose/camera_node/frame_matcher.hpp"

#include <cstdlib>

namespace hullpose::trigger {

FrameMatcher::FrameMatcher(const FrameMatcherConfig& config) : config_(config) {
  frames_.reserve(FrameMatcherConfig::kFrames);
  edges_.reserve(FrameMatcherConfig::kEdges);
}

void FrameMatcher::on_frame(int64_t frame_id, int64_t frame_us) {
  if (frames_.size() == FrameMatcherConfig::kFrames) frames_.erase(frames_.begin());
  frames_.push_back({frame_id, frame_us, false});
}

void FrameMatcher::on_edge(const MappedEdge& edge) {
  if (edges_.size() == FrameMatcherConfig::kEdges) {
    edges_.erase(edges_.begin());
    counters_.add("edge_overflow");
  }
  edges_.push_back(edge);
}

void FrameMatcher::poll(int64_t now_us, std::vector<TaggedFrame>& out) {
  size_t done = 0;
  for (; done < edges_.size(); ++done) {
    const MappedEdge& e = edges_[done];
    const bool frame_after = !frames_.empty() && frames_.back().us >= e.edge_us;
    if (!frame_after && now_us - e.edge_us <= config_.max_residual_us)
      break;  // a nearer frame may come
    Frame* best = nullptr;
    for (Frame& f : frames_) {
      if (!f.used && std::llabs(f.us - e.edge_us) <= config_.max_residual_us &&
          (!best || std::llabs(f.us - e.edge_us) < std::llabs(best->us - e.edge_us)))
        best = &f;
    }
    if (!best) {
      counters_.add("no_frame");
      continue;
    }
    best->used = true;
    out.push_back({best->id, best->us, e, best->us - e.edge_us});
  }
  edges_.erase(edges_.begin(), edges_.begin() + static_cast<std::ptrdiff_t>(done));
}

}  // namespace hullpose::trigger
