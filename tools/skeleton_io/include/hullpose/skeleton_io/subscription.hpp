#pragma once
// The live side of every consumer: an LCM subscription to SKELETON (and, for those who want the
// rig's health, STATUS). Bytes are bounds-checked (common/lcm_wire.hpp) before the lcm-gen
// decoder; malformed messages are counted, never thrown. Handlers run on the thread that calls
// poll(), the consumer's main loop.
#include <functional>
#include <hullpose_msg/node_status_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>

#include "hullpose/common/counters.hpp"
#include "hullpose/skeleton_io/take.hpp"

namespace hullpose::skeleton_io {

struct SubscriptionOptions {
  std::string lcm_url;  // "" = LCM's default
  std::string skeleton_channel = "SKELETON";
  std::string status_channel = "STATUS";  // "" = not subscribed
  std::string rig_id;  // "" = any rig; otherwise other rigs are counted and dropped
};

class Subscription {
 public:
  using SkeletonHandler = std::function<void(const SkeletonFrame&, int64_t received_mono_us)>;
  using StatusHandler = std::function<void(const hullpose_msg::node_status_t&)>;

  // Throws hullpose::Error when the LCM URL cannot be opened.
  Subscription(const SubscriptionOptions& options, SkeletonHandler on_skeleton,
               StatusHandler on_status = {});
  ~Subscription();
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;

  // Handles what has arrived, waiting up to timeout_ms for the first message. False on an LCM
  // error.
  bool poll(int timeout_ms);
  const Counters& counters() const { return counters_; }
  lcm::LCM& bus() { return *bus_; }

 private:
  void on_skeleton(const lcm::ReceiveBuffer* rb, const std::string& channel);
  void on_status(const lcm::ReceiveBuffer* rb, const std::string& channel);

  SubscriptionOptions options_;
  std::unique_ptr<lcm::LCM> bus_;
  SkeletonHandler on_skeleton_;
  StatusHandler on_status_;
  Counters counters_;
  hullpose_msg::skeleton_t msg_;
  hullpose_msg::node_status_t status_;
  SkeletonFrame frame_;
};

}  // namespace hullpose::skeleton_io
