#include "hullpose/camera_node/trigger_listener.hpp"

namespace hullpose::trigger {

TriggerListener::TriggerListener(const ListenerConfig& config, EdgeSource& edges)
    : config_(config), edges_(edges), mapper_(config.mapper), matcher_(config.matcher) {
  mapped_.reserve(MapperConfig::kEdges);
}

void TriggerListener::on_announcement(const hullpose_msg::trigger_t& msg, int64_t received_us) {
  if (msg.rig_id != config_.rig_id) {
    ++foreign_;
    return;
  }
  mapper_.on_announcement({msg.seq, msg.utime, msg.epoch, msg.period_us, received_us});
}

void TriggerListener::poll(int64_t now_us, std::vector<TaggedFrame>& out) {
  int64_t edge = 0;
  while (edges_.read(edge)) {
    mapper_.on_edge(edge);
    if (config_.expose_after_edge_us >= 0)
      matcher_.on_frame(exposed_++, edge + config_.expose_after_edge_us);
  }
  mapped_.clear();
  mapper_.poll(now_us, mapped_);
  for (const MappedEdge& e : mapped_) matcher_.on_edge(e);
  matcher_.poll(now_us, out);
}

}  // namespace hullpose::trigger
