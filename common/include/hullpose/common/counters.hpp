#pragma once
// Named event counters for per-frame paths: every dropped message or frame is counted here
// under a reason ("late", "duplicate", "foreign_rig", "decode_error", ...) and shows up on the
// STATUS channel. Thread-safe; a name allocates only the first time it is used.
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hullpose {

class Counters {
 public:
  void add(std::string_view name, int64_t n = 1);
  int64_t get(std::string_view name) const;
  int64_t total() const;
  std::vector<std::pair<std::string, int64_t>> snapshot() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::pair<std::string, int64_t>> values_;  // few names: a flat list beats a map
};

}  // namespace hullpose
