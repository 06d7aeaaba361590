#pragma once
// The trigger master: one pulse per period on the trigger line, scheduled on absolute times so
// that a late wake-up never shifts the pulses after it, and one trigger_t announcement per pulse
// (sequence number, edge time on the master's clock, epoch). It measures its own jitter
// (actual rising edge minus scheduled edge).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <hullpose_msg/trigger_t.hpp>
#include <mutex>
#include <string>
#include <vector>

#include "hullpose/common/clock.hpp"
#include "hullpose/firmware_sync/trigger_line.hpp"

namespace hullpose::sync {

struct TriggerMasterConfig {
  std::string rig_id;
  double rate_hz = 30.0;
  int pulse_width_us = 1000;
  void validate() const;  // throws hullpose::Error naming the field
};

// Wake-up error of the rising edges, microseconds; keeps the last kWindow samples for p99.
class JitterStats {
 public:
  static constexpr size_t kWindow = 1024;
  JitterStats() {
    window_.resize(kWindow);
    scratch_.resize(kWindow);
  }
  void add(int64_t late_us);
  int64_t count() const { return count_; }
  double mean_us() const {
    return count_ ? static_cast<double>(sum_) / static_cast<double>(count_) : 0.0;
  }
  int64_t max_us() const { return max_; }
  // 99th percentile over the window (sorts a preallocated copy).
  int64_t p99_us();

 private:
  std::vector<int64_t> window_, scratch_;
  int64_t count_ = 0, sum_ = 0, max_ = 0;
};

class TriggerMaster {
 public:
  using Announce = std::function<void(const hullpose_msg::trigger_t&)>;
  // epoch: a random id for this run of the master (new_epoch()).
  TriggerMaster(const TriggerMasterConfig& config, TriggerLine& line, Clock& clock,
                Announce announce, int64_t epoch);

  // Waits for the next slot, drives one pulse and announces it. Returns its sequence number.
  int64_t pulse();
  // Pulses while running, until keep_going() is false; while stopped, polls keep_going() every
  // 100 ms and wakes at once on start().
  void run(const std::function<bool()>& keep_going);

  // Thread-safe controls; a rate change applies from the next pulse on; start() after stop()
  // begins a new pulse train one period later (sequence numbers and epoch continue).
  void start();
  void stop();
  void set_rate(double rate_hz);
  bool running() const { return running_.load(); }

  int64_t next_seq() const { return seq_; }
  int64_t epoch() const { return epoch_; }
  int64_t period_us() const { return period_us_.load(); }
  int64_t missed_slots() const { return missed_slots_; }
  JitterStats& jitter() { return jitter_; }

 private:
  TriggerMasterConfig config_;
  TriggerLine& line_;
  Clock& clock_;
  Announce announce_;
  int64_t epoch_;
  int64_t seq_ = 0;
  std::atomic<int64_t> period_us_;
  int64_t next_edge_us_ = -1;  // monotonic; -1: schedule from now
  int64_t missed_slots_ = 0;
  JitterStats jitter_;
  hullpose_msg::trigger_t msg_;
  std::atomic<bool> running_{true};
  std::atomic<bool> reschedule_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
};

// A random, non-zero epoch id (std::random_device).
int64_t new_epoch();
int64_t period_from_rate(double rate_hz);

}  // namespace hullpose::sync
