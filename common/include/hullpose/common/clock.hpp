#pragma once
// Time as components see it, behind an interface so that tests drive it (Drake injects its
// clock the same way): the fusion service's deadlines, the trigger client's clock mapping and the
// trigger master's pulse train read this, never the system clock directly.
#include <cstdint>

namespace hullpose {

class Clock {
 public:
  virtual ~Clock() = default;
  // Microseconds on a steady clock (CLOCK_MONOTONIC): durations and deadlines.
  virtual int64_t monotonic_us() = 0;
  // Microseconds since the Unix epoch (CLOCK_REALTIME): the `utime` of messages.
  virtual int64_t realtime_utime() = 0;
  // Absolute-time sleep on the monotonic clock: a late wake-up does not shift later deadlines.
  virtual void sleep_until_monotonic_us(int64_t t_us) = 0;
};

// The system's clocks (clock_gettime, clock_nanosleep(TIMER_ABSTIME)). One per process is enough.
class SystemClock final : public Clock {
 public:
  int64_t monotonic_us() override;
  int64_t realtime_utime() override;
  void sleep_until_monotonic_us(int64_t t_us) override;
};
SystemClock& system_clock();

// Test clock: time moves only when the test moves it; sleeping jumps to the target, plus an
// injected wake-up lateness (scheduler latency).
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
  void set_monotonic_us(int64_t t_us) { now_ = t_us; }
  int64_t realtime_minus_monotonic_us() const { return offset_; }
  // The next sleep wakes up this much after its target.
  void inject_lateness(int64_t us) { next_lateness_us_ = us; }

 private:
  int64_t now_ = 1'000'000;
  int64_t offset_;
  int64_t next_lateness_us_ = 0;
};

}  // namespace hullpose
