#include "hullpose/common/time.hpp"

#include <ctime>

namespace hullpose {
namespace {
int64_t read_us(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1'000;
}
}  // namespace

int64_t monotonic_us() {
  return read_us(CLOCK_MONOTONIC);
}
int64_t realtime_utime() {
  return read_us(CLOCK_REALTIME);
}

}  // namespace hullpose
