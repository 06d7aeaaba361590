#pragma once
// The live side of every consumer: subscriptions to SKELETON (and, for those who want them, the
// rig's health on STATUS and the optional coarse hull on HULL) on the process's one bus
// (common/bus.hpp, opened by main). Bytes go through wire::decode (bounds-checked before lcm-gen's
// decoder), a hull then through msg::from_message (every field checked); malformed messages and
// other rigs' are counted, never thrown. Handlers run on the thread that calls poll() — the
// consumer's main loop, or a server's I/O thread watching bus.fd().
#include <functional>
#include <hullpose_msg/hull_t.hpp>
#include <hullpose_msg/node_status_t.hpp>
#include <string>
#include <vector>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/msg/hull.hpp"
#include "hullpose/skeleton_io/take.hpp"

namespace hullpose::skeleton_io {

struct SubscriptionOptions {
  std::string skeleton_channel = "SKELETON";
  std::string status_channel = "STATUS";  // "" = not subscribed
  std::string hull_channel = "HULL";      // "" = not subscribed (nor without a hull handler)
  std::string rig_id;  // "" = any rig; otherwise other rigs are counted and dropped
};

class Subscription {
 public:
  using SkeletonHandler = std::function<void(const SkeletonFrame&, int64_t received_mono_us)>;
  using StatusHandler = std::function<void(const hullpose_msg::node_status_t&)>;
  using HullHandler = std::function<void(const msg::CoarseHull&)>;

  // `bus` outlives the subscription.
  Subscription(bus::Bus& bus, const SubscriptionOptions& options, SkeletonHandler on_skeleton,
               StatusHandler on_status = {}, HullHandler on_hull = {});

  // Handles everything that has arrived, waiting up to timeout_ms for the first message.
  void poll(int timeout_ms);
  int fd() const { return bus_.fd(); }
  const Counters& counters() const { return counters_; }

 private:
  void on_skeleton(std::span<const uint8_t> bytes);
  void on_status(std::span<const uint8_t> bytes);
  void on_hull(std::span<const uint8_t> bytes);

  bus::Bus& bus_;
  SubscriptionOptions options_;
  SkeletonHandler on_skeleton_;
  StatusHandler on_status_;
  HullHandler on_hull_;
  Counters counters_;
  hullpose_msg::skeleton_t msg_;
  hullpose_msg::node_status_t status_;
  hullpose_msg::hull_t hull_msg_;
  msg::CoarseHull hull_;
  SkeletonFrame frame_;
  std::vector<bus::Subscription> subscriptions_;
};

}  // namespace hullpose::skeleton_io
