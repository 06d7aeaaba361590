#pragma once
// A scratch directory of this test process: `name` plus its pid under the temp directory, made
// empty at construction and removed at destruction. Two runs of one test binary can overlap on
// one machine (make test beside make cross's emulated run, two checkouts): with a shared fixed
// path, one run's write_dataset() removed and rewrote the files the other was replaying (make
// cross: a node learnt 15 of 20 background frames, then saw no frame at all).
#include <unistd.h>

#include <filesystem>
#include <string>

namespace hullpose::test {

struct ScratchDir {
  std::filesystem::path path;
  explicit ScratchDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;  // never throw from a destructor; a leftover directory is harmless
    std::filesystem::remove_all(path, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
};

}  // namespace hullpose::test
