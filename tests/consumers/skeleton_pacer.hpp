#pragma once
// Skeletons on SKELETON at a steady rate, as the fusion host sends them on the rig's trigger
// clock: frame k carries trigger sequence k and utime start + k / rate, and goes out at its
// slot on the steady clock. Shared by consumers_sim_rig and consumers_bench.
#include <chrono>
#include <cstdint>
#include <hullpose_msg/skeleton_t.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/msg/wire.hpp"
#include "hullpose/skeleton_io/take.hpp"

namespace hullpose::consumers_test {

class SkeletonPacer {
 public:
  SkeletonPacer(bus::Bus& bus, std::string rig_id, double rate_hz)
      : bus_(bus),
        rig_id_(std::move(rig_id)),
        rate_hz_(rate_hz),
        period_(static_cast<int64_t>(1e6 / rate_hz)),
        next_(std::chrono::steady_clock::now()),
        start_utime_(realtime_utime()) {}

  // Stamps `frame` as frame k (seq, utime) and publishes it.
  void publish(int64_t k, skeleton_io::SkeletonFrame& frame) {
    frame.seq = k;
    frame.utime = start_utime_ + static_cast<int64_t>(static_cast<double>(k) * 1e6 / rate_hz_);
    skeleton_io::to_message(frame, rig_id_, msg_);
    wire::publish(bus_, "SKELETON", msg_, scratch_);
  }
  // Sleeps until the next frame's slot.
  void wait_next() {
    next_ += period_;
    std::this_thread::sleep_until(next_);
  }

  // Scratch for the caller's other messages on the same bus (STATUS).
  std::vector<uint8_t>& scratch() { return scratch_; }

 private:
  bus::Bus& bus_;
  std::string rig_id_;
  double rate_hz_;
  std::chrono::microseconds period_;
  std::chrono::steady_clock::time_point next_;
  int64_t start_utime_;
  hullpose_msg::skeleton_t msg_;
  std::vector<uint8_t> scratch_;
};

}  // namespace hullpose::consumers_test
