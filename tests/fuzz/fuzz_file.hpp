#pragma once
// For fuzz targets of file readers, which fuzz each reader's parse-from-text entry (the file
// readers are thin wrappers that read the file and call it), and the readers' contract: a reader
// returns or throws hullpose::Error. Any other exception escapes LLVMFuzzerTestOneInput, which
// libFuzzer reports as a crash, as it does a signal or a sanitizer finding.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "hullpose/common/log.hpp"

namespace hullpose::fuzz {

inline std::string text(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A reader's warnings (e.g. a repaired rotation) would go to stderr on every execution.
inline void quiet_logs() {
  static const bool once = (log::set_levels("*:off"), true);
  (void)once;
}

inline std::vector<uint8_t> bytes_of(const std::string& s) {
  return {s.begin(), s.end()};
}

inline std::vector<uint8_t> read_all(const std::filesystem::path& p) {
  std::vector<uint8_t> out;
  if (std::FILE* f = std::fopen(p.c_str(), "rb")) {
    int c;
    while ((c = std::fgetc(f)) != EOF) out.push_back(static_cast<uint8_t>(c));
    std::fclose(f);
  }
  return out;
}

}  // namespace hullpose::fuzz
