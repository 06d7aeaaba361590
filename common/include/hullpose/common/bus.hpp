#pragma once
// The message bus every process talks through: LCM-encoded bytes on named channels.
//
// One Bus per process: main() opens it with open_bus(url) and passes it down to every component
// (the camera node's publisher and trigger stage, the fusion service, the trigger master, the
// listener). Tests open "memq://" (LCM's in-process provider: no sockets, deterministic) and run
// the same components. Components never open LCM themselves.
//
// Ownership: the Bus outlives every Subscription made on it. publish() may be called from any
// thread; handlers run on the thread that calls handle().
//
// Typed messages go through lcm_types' wire::publish / wire::decode, which bounds-check the bytes
// before lcm-gen's decoder sees them. A layer on the raw bytes — message authentication over
// channel name + payload (issue #19) — belongs in ONE place: a Bus that wraps the one open_bus()
// returns (open_bus() in common/src/bus.cpp is where every process gets its bus), checking on
// receive before calling the handler and appending on publish.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

namespace hullpose::bus {

using Handler = std::function<void(std::span<const uint8_t> bytes, const std::string& channel)>;

// Unsubscribes when destroyed (or reset()). Move-only.
class Subscription {
 public:
  Subscription() = default;
  explicit Subscription(std::function<void()> cancel) : cancel_(std::move(cancel)) {}
  ~Subscription() { reset(); }
  Subscription(Subscription&& o) noexcept : cancel_(std::move(o.cancel_)) { o.cancel_ = nullptr; }
  Subscription& operator=(Subscription&& o) noexcept {
    if (this != &o) {
      reset();
      cancel_ = std::move(o.cancel_);
      o.cancel_ = nullptr;
    }
    return *this;
  }
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;
  void reset() {
    if (cancel_) cancel_();
    cancel_ = nullptr;
  }

 private:
  std::function<void()> cancel_;
};

class Bus {
 public:
  virtual ~Bus() = default;
  // Sends `bytes` on `channel`; false if the transport refused it (the caller counts it).
  virtual bool publish(const std::string& channel, std::span<const uint8_t> bytes) = 0;
  // `handler` sees every message on `channel` (an LCM channel name or regex). Up to
  // queue_capacity messages wait for handle(); older ones are dropped by LCM.
  [[nodiscard]] virtual Subscription subscribe(const std::string& channel, Handler handler,
                                               int queue_capacity = 30) = 0;
  // Dispatches one pending message, waiting up to timeout_ms for it (0: only what is pending).
  // Returns true if a message was handled (false also when LCM dropped what arrived).
  virtual bool handle(int timeout_ms) = 0;
  // Readable when a message is pending (to poll() it with other inputs).
  virtual int fd() const = 0;
  // What was opened, for logs and errors ("udpm://239.255.76.67:7667?ttl=0", "memq://").
  virtual const std::string& url() const = 0;
};

// LCM at `url` ("" = LCM's default, LCM_DEFAULT_URL; "memq://" in tests). Throws hullpose::Error
// naming the URL when LCM cannot open it (bad URL, no multicast route).
std::unique_ptr<Bus> open_bus(const std::string& url);

}  // namespace hullpose::bus
