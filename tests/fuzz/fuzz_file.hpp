#pragma once
// For fuzz targets of file readers: the input bytes as a file (in /dev/shm when there is one,
// one per process and suffix), and the readers' contract: a reader returns or throws
// hullpose::Error. Any other exception escapes LLVMFuzzerTestOneInput, which libFuzzer reports
// as a crash, as it does a signal or a sanitizer finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace hullpose::fuzz {

inline std::string input_file(const uint8_t* data, size_t size, const std::string& suffix) {
  static const std::filesystem::path dir =
      std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
  const std::string path =
      (dir / ("hullpose-fuzz-" + std::to_string(::getpid()) + suffix)).string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
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
