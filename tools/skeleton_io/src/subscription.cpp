#include "hullpose/skeleton_io/subscription.hpp"

#include <poll.h>

#include <cerrno>

#include "hullpose/common/check.hpp"
#include "hullpose/common/lcm_wire.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::skeleton_io {

HULLPOSE_LOG_CATEGORY(Subscribe, "subscribe");

Subscription::Subscription(const SubscriptionOptions& options, SkeletonHandler on_skeleton,
                           StatusHandler on_status)
    : options_(options),
      bus_(std::make_unique<lcm::LCM>(options.lcm_url)),
      on_skeleton_(std::move(on_skeleton)),
      on_status_(std::move(on_status)) {
  HULLPOSE_THROW_UNLESS(bus_->good(), "LCM '"
                                          << (options.lcm_url.empty() ? "default" : options.lcm_url)
                                          << "' cannot be opened");
  // LCM's own queue per subscription: bounded, so a stalled consumer drops at the socket.
  bus_->subscribe(options_.skeleton_channel, &Subscription::on_skeleton, this)
      ->setQueueCapacity(64);
  if (!options_.status_channel.empty() && on_status_)
    bus_->subscribe(options_.status_channel, &Subscription::on_status, this)->setQueueCapacity(256);
}

Subscription::~Subscription() = default;

bool Subscription::poll(int timeout_ms) {
  pollfd p{bus_->getFileno(), POLLIN, 0};
  const int ready = ::poll(&p, 1, timeout_ms);
  if (ready < 0) return errno == EINTR;  // a signal (the caller checks its stop flag)
  if (ready == 0) return true;
  // Drain what is queued: a socket watched edge-triggered (asio) signals only new data.
  for (int handled = 0; handled < 1000; ++handled) {
    const int r = bus_->handleTimeout(0);
    if (r < 0) return false;
    if (r == 0) break;
  }
  return true;
}

void Subscription::on_skeleton(const lcm::ReceiveBuffer* rb, const std::string&) {
  const int64_t now = monotonic_us();
  const auto size = static_cast<int>(rb->data_size);
  if (!wire::skeleton_ok(rb->data, rb->data_size) || msg_.decode(rb->data, 0, size) != size ||
      !from_message(msg_, frame_)) {
    counters_.add("malformed_skeleton");
    HULLPOSE_LOG(Subscribe, Debug)
        << "malformed skeleton_t (" << rb->data_size << " bytes) dropped";
    return;
  }
  if (!options_.rig_id.empty() && msg_.rig_id != options_.rig_id) {
    counters_.add("foreign_rig");
    return;
  }
  on_skeleton_(frame_, now);
}

void Subscription::on_status(const lcm::ReceiveBuffer* rb, const std::string&) {
  const auto size = static_cast<int>(rb->data_size);
  if (!wire::status_ok(rb->data, rb->data_size) || status_.decode(rb->data, 0, size) != size) {
    counters_.add("malformed_status");
    return;
  }
  if (!options_.rig_id.empty() && status_.rig_id != options_.rig_id) {
    counters_.add("foreign_rig");
    return;
  }
  on_status_(status_);
}

}  // namespace hullpose::skeleton_io
