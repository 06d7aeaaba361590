#pragma once
#include <cstdint>

namespace hullpose {

// Microseconds on CLOCK_MONOTONIC: for durations and deadlines inside one process.
int64_t monotonic_us();
// Microseconds since the Unix epoch (CLOCK_REALTIME): the `utime` of LCM messages.
int64_t realtime_utime();

// Measures one stage: construct, run the stage, read elapsed_us().
class StageTimer {
 public:
  StageTimer() : start_(monotonic_us()) {}
  int64_t elapsed_us() const { return monotonic_us() - start_; }
  void restart() { start_ = monotonic_us(); }

 private:
  int64_t start_;
};

}  // namespace hullpose
