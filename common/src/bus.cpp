#include "hullpose/common/bus.hpp"

#include <lcm/lcm-cpp.hpp>
#include <list>
#include <mutex>

#include "hullpose/common/check.hpp"

namespace hullpose::bus {
namespace {

class LcmBus final : public Bus {
 public:
  explicit LcmBus(const std::string& url) : url_(url.empty() ? "default LCM URL" : url), lcm_(url) {
    HULLPOSE_THROW_UNLESS(
        lcm_.good(), "LCM '" << url_ << "' cannot be opened (bad URL, or no multicast route?)");
  }

  bool publish(const std::string& channel, std::span<const uint8_t> bytes) override {
    return lcm_.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size())) == 0;
  }

  Subscription subscribe(const std::string& channel, Handler handler, int queue_capacity) override {
    std::lock_guard lock(mutex_);
    auto it = slots_.insert(slots_.end(), Slot{std::move(handler), nullptr});
    it->lcm = lcm_.subscribeFunction(channel, &LcmBus::dispatch, &*it);
    it->lcm->setQueueCapacity(queue_capacity);
    return Subscription([this, it] {
      std::lock_guard unsubscribing(mutex_);
      lcm_.unsubscribe(it->lcm);
      slots_.erase(it);
    });
  }

  bool handle(int timeout_ms) override {
    // LCM returns -1 for a datagram it could not deliver (a lost fragment of a large message, a
    // full subscription queue): a drop on the network, not the end of the bus.
    return lcm_.handleTimeout(timeout_ms) > 0;
  }

  int fd() const override { return const_cast<lcm::LCM&>(lcm_).getFileno(); }
  const std::string& url() const override { return url_; }

 private:
  struct Slot {
    Handler handler;
    lcm::Subscription* lcm;
  };

  // Every received byte passes here.
  static void dispatch(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Slot* slot) {
    slot->handler({static_cast<const uint8_t*>(rbuf->data), rbuf->data_size}, channel);
  }

  std::string url_;
  lcm::LCM lcm_;
  std::mutex mutex_;       // subscribe/unsubscribe from any thread
  std::list<Slot> slots_;  // stable addresses: LCM holds pointers to them
};

}  // namespace

std::unique_ptr<Bus> open_bus(const std::string& url) {
  return std::make_unique<LcmBus>(url);
}

}  // namespace hullpose::bus
