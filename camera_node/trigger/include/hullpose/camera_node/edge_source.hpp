#pragma once
// Rising edges of the trigger input, each with the time the kernel stamped it.
//   gpiod:CHIP:OFFSET  libgpiod (v1) line events; kernel stamps are CLOCK_MONOTONIC
//   wire:PATH          the simulated wire of hullpose-trigger-master --line wire:PATH
//   SimEdgeSource      edges pushed by tests
// Times are on the node clock: the process Clock's monotonic time (CLOCK_MONOTONIC in production)
// plus a configured offset (a board whose clock is off by that much; 0 in production).
// Everything that compares with edge times (announcement receive times, sensor timestamps) must
// use NodeClock with the same offset and Clock.
#include <cstdint>
#include <deque>
#include <memory>
#include <string>

#include "hullpose/common/clock.hpp"

namespace hullpose::trigger {

struct NodeClock {
  int64_t offset_us = 0;
  Clock* clock = &system_clock();  // tests: a SimClock
  int64_t now_us() const { return clock->monotonic_us() + offset_us; }
  // Maps the sensor's realtime timestamps onto the node clock.
  int64_t realtime_minus_node_us() const { return clock->realtime_utime() - now_us(); }
};

class EdgeSource {
 public:
  virtual ~EdgeSource() = default;
  // A descriptor that becomes readable when an edge is pending, or -1 (poll read() instead).
  virtual int fd() const = 0;
  // Non-blocking: the next pending rising edge's time on the node clock, false if none.
  virtual bool read(int64_t& edge_us) = 0;
  virtual std::string describe() const = 0;
};

// Throws hullpose::Error naming the spec and the device when it cannot be opened (a wire: is
// waited for up to connect_timeout_ms).
std::unique_ptr<EdgeSource> open_edge_source(const std::string& spec, const NodeClock& clock,
                                             int connect_timeout_ms = 0);

class SimEdgeSource final : public EdgeSource {
 public:
  void push(int64_t edge_us) { edges_.push_back(edge_us); }
  int fd() const override { return -1; }
  bool read(int64_t& edge_us) override {
    if (edges_.empty()) return false;
    edge_us = edges_.front();
    edges_.pop_front();
    return true;
  }
  std::string describe() const override { return "sim"; }

 private:
  std::deque<int64_t> edges_;
};

}  // namespace hullpose::trigger
