#include "hullpose/skeleton_io/subscription.hpp"

#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/msg/wire.hpp"

namespace hullpose::skeleton_io {

HULLPOSE_LOG_CATEGORY(Subscribe, "subscribe");

Subscription::Subscription(bus::Bus& bus, const SubscriptionOptions& options,
                           SkeletonHandler skeleton_handler, StatusHandler status_handler,
                           HullHandler hull_handler)
    : bus_(bus),
      options_(options),
      on_skeleton_(std::move(skeleton_handler)),
      on_status_(std::move(status_handler)),
      on_hull_(std::move(hull_handler)) {
  // LCM's queue per subscription is bounded: a stalled consumer drops at the socket.
  subscriptions_.push_back(bus_.subscribe(
      options_.skeleton_channel,
      [this](std::span<const uint8_t> b, const std::string&) { on_skeleton(b); }, 64));
  if (!options_.status_channel.empty() && on_status_)
    subscriptions_.push_back(bus_.subscribe(
        options_.status_channel,
        [this](std::span<const uint8_t> b, const std::string&) { on_status(b); }, 256));
  // A few hulls at most: they come at a low rate and only the newest is worth drawing.
  if (!options_.hull_channel.empty() && on_hull_)
    subscriptions_.push_back(bus_.subscribe(
        options_.hull_channel,
        [this](std::span<const uint8_t> b, const std::string&) { on_hull(b); }, 8));
}

void Subscription::poll(int timeout_ms) {
  if (!bus_.handle(timeout_ms)) return;
  // Drain what is queued: a socket watched edge-triggered (asio) signals only new data.
  for (int handled = 1; handled < 1000 && bus_.handle(0); ++handled) {
  }
}

void Subscription::on_skeleton(std::span<const uint8_t> bytes) {
  const int64_t now = monotonic_us();
  if (!wire::decode(bytes, msg_) || !from_message(msg_, frame_)) {
    counters_.add("malformed_skeleton");
    HULLPOSE_LOG(Subscribe, Debug) << "malformed skeleton_t (" << bytes.size() << " bytes) dropped";
    return;
  }
  if (!options_.rig_id.empty() && msg_.rig_id != options_.rig_id) {
    counters_.add("foreign_rig");
    return;
  }
  on_skeleton_(frame_, now);
}

void Subscription::on_status(std::span<const uint8_t> bytes) {
  if (!wire::decode(bytes, status_)) {
    counters_.add("malformed_status");
    return;
  }
  if (!options_.rig_id.empty() && status_.rig_id != options_.rig_id) {
    counters_.add("foreign_rig");
    return;
  }
  on_status_(status_);
}

void Subscription::on_hull(std::span<const uint8_t> bytes) {
  if (!wire::decode(bytes, hull_msg_)) {
    counters_.add("malformed_hull");
    HULLPOSE_LOG(Subscribe, Debug) << "malformed hull_t (" << bytes.size() << " bytes) dropped";
    return;
  }
  if (!options_.rig_id.empty() && hull_msg_.rig_id != options_.rig_id) {
    counters_.add("foreign_rig");
    return;
  }
  if (const msg::HullError e = msg::from_message(hull_msg_, hull_); e != msg::HullError::kNone) {
    counters_.add(std::string("invalid_hull_") + msg::to_string(e));
    HULLPOSE_LOG(Subscribe, Debug)
        << "hull_t of trigger " << hull_msg_.trigger_seq << " dropped: " << msg::to_string(e);
    return;
  }
  on_hull_(hull_);
}

}  // namespace hullpose::skeleton_io
