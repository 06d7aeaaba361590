#include "hullpose/common/clock.hpp"

#include <cerrno>
#include <ctime>

#include "hullpose/common/time.hpp"

namespace hullpose {

int64_t SystemClock::monotonic_us() {
  return hullpose::monotonic_us();
}
int64_t SystemClock::realtime_utime() {
  return hullpose::realtime_utime();
}

void SystemClock::sleep_until_monotonic_us(int64_t t_us) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t_us / 1'000'000);
  ts.tv_nsec = static_cast<long>((t_us % 1'000'000) * 1000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

SystemClock& system_clock() {
  static SystemClock clock;
  return clock;
}

}  // namespace hullpose
