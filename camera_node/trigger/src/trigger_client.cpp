#include "hullpose/camera_node/trigger_client.hpp"

#include <poll.h>

#include <algorithm>

#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/msg/wire.hpp"

namespace hullpose::trigger {

TriggerClient::TriggerClient(bus::Bus& bus, EdgeSource& edges, const ListenerConfig& config,
                             const NodeClock& clock, const std::string& channel)
    : bus_(bus), edges_(edges), clock_(clock), listener_(config, edges) {
  subscription_ = wire::subscribe(
      bus_, channel, msg_, counters_, "malformed_trigger",
      [this](const hullpose_msg::trigger_t& t) { listener_.on_announcement(t, clock_.now_us()); });
  tagged_.reserve(MapperConfig::kEdges);
  for (const char* name : {"malformed_trigger", "tag_after_timeout", "untagged_frame", "overrun"})
    counters_.add(name, 0);
}

TriggerClient::~TriggerClient() = default;

template <class Done>
bool TriggerClient::pump(int wait_ms, Done&& done) {
  // Waiting is real time (poll); the times of edges, announcements and frames come from the
  // node clock, which tests drive.
  const int64_t until = monotonic_us() + int64_t{wait_ms} * 1000;
  for (;;) {
    pollfd fds[2] = {{edges_.fd(), POLLIN, 0}, {bus_.fd(), POLLIN, 0}};
    while (bus_.handle(0)) {
    }
    const size_t before = tagged_.size();
    listener_.poll(clock_.now_us(), tagged_);
    if (done(before)) return true;
    const int64_t left_us = until - monotonic_us();
    if (left_us <= 0) return false;
    if (fds[0].fd >= 0 && listener_.idle()) {
      // Nothing pending: sleep until the next edge. The bus carries the whole rig's traffic (every
      // node's silhouettes); its TRIGGER announcement follows the edge within a fraction of a
      // millisecond and is handled then, so the node wakes once per trigger, not once per message.
      ::poll(&fds[0], 1, static_cast<int>(1 + left_us / 1000));
    } else {
      ::poll(fds[0].fd >= 0 ? fds : &fds[1], fds[0].fd >= 0 ? 2 : 1,
             static_cast<int>(std::min<int64_t>(1 + left_us / 1000, 5)));
    }
  }
}

int64_t TriggerClient::to_node_clock(int64_t frame_utime) const {
  // Sensor timestamps are on the realtime clock, edges on the monotonic one (+ the board offset).
  return frame_utime - clock_.realtime_minus_node_us();
}

void TriggerClient::offer(int64_t frame_id, int64_t frame_utime,
                          std::vector<TaggedFrame>& decided) {
  listener_.on_frame(frame_id, to_node_clock(frame_utime));
  tagged_.clear();
  pump(0, [](size_t) { return true; });
  decided.assign(tagged_.begin(), tagged_.end());
  tagged_.clear();
}

std::optional<TaggedFrame> TriggerClient::tag(int64_t frame_id, int64_t frame_utime, int wait_ms) {
  listener_.on_frame(frame_id, to_node_clock(frame_utime));
  std::optional<TaggedFrame> found;
  tagged_.clear();
  pump(wait_ms, [&](size_t from) {
    for (size_t i = from; i < tagged_.size(); ++i) {
      if (tagged_[i].frame_id == frame_id) {
        found = tagged_[i];
      } else {
        counters_.add("tag_after_timeout");  // an earlier frame, already given up on
      }
    }
    tagged_.clear();
    return found.has_value();
  });
  if (!found) counters_.add("untagged_frame");
  return found;
}

std::optional<TaggedFrame> TriggerClient::next_exposure(int wait_ms) {
  if (next_tagged_ == tagged_.size()) {
    tagged_.clear();
    next_tagged_ = 0;
    if (!pump(wait_ms, [&](size_t) { return !tagged_.empty(); })) return std::nullopt;
  }
  // Like a camera's driver queue: a node that falls behind finds at most kSensorBuffers exposures
  // waiting; older ones were overwritten (counted), so it catches up instead of lagging for good.
  const size_t waiting = tagged_.size() - next_tagged_;
  if (waiting > kSensorBuffers) {
    counters_.add("overrun", static_cast<int64_t>(waiting - kSensorBuffers));
    next_tagged_ = tagged_.size() - kSensorBuffers;
  }
  return tagged_[next_tagged_++];
}

}  // namespace hullpose::trigger
