#include "hullpose/common/counters.hpp"

namespace hullpose {

void Counters::add(std::string_view name, int64_t n) {
  std::lock_guard lock(mutex_);
  for (auto& [key, value] : values_) {
    if (key == name) {
      value += n;
      return;
    }
  }
  values_.emplace_back(std::string(name), n);
}

int64_t Counters::get(std::string_view name) const {
  std::lock_guard lock(mutex_);
  for (const auto& [key, value] : values_)
    if (key == name) return value;
  return 0;
}

int64_t Counters::total() const {
  std::lock_guard lock(mutex_);
  int64_t sum = 0;
  for (const auto& entry : values_) sum += entry.second;
  return sum;
}

std::vector<std::pair<std::string, int64_t>> Counters::snapshot() const {
  std::lock_guard lock(mutex_);
  return values_;
}

}  // namespace hullpose
