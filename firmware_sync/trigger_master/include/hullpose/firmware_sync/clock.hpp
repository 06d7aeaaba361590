#pragma once
// The master's view of time, behind an interface so that tests drive it without sleeping.
#include <cstdint>

namespace hullpose::sync {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t monotonic_us() = 0;
  virtual int64_t realtime_utime() = 0;
  // Absolute-time sleep on the monotonic clock: a late wake-up does not shift later pulses.
  virtual void sleep_until_monotonic_us(int64_t t_us) = 0;
};

// CLOCK_MONOTONIC / CLOCK_REALTIME, clock_nanosleep(TIMER_ABSTIME).
class SystemClock final : public Clock {
 public:
  int64_t monotonic_us() override;
  int64_t realtime_utime() override;
  void sleep_until_monotonic_us(int64_t t_us) override;
};

// Test clock: sleeping jumps to the target time plus an injected wake-up lateness.
class SimClock final : public Clock {
 public:
  explicit SimClock(int64_t realtime_minus_monotonic_us = 1'700'000'000'000'000)
      : offset_(realtime_minus_monotonic_us) {}
  int64_t monotonic_us() override { return now_; }
  int64_t realtime_utime() override { return now_ + offset_; }
  void sleep_until_monotonic_us(int64_t t_us) override {
    if (t_us > now_) now_ = t_us;
    now_ += next_lateness_us_;
    next_lateness_us_ = 0;
  }
  void advance(int64_t us) { now_ += us; }
  // The next sleep wakes up this much after its target (scheduler latency).
  void inject_lateness(int64_t us) { next_lateness_us_ = us; }

 private:
  int64_t now_ = 1'000'000;
  int64_t offset_;
  int64_t next_lateness_us_ = 0;
};

}  // namespace hullpose::sync
