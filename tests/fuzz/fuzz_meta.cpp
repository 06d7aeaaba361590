// Fuzz target: the dataset metadata reader (common/dataset.hpp parse_meta, which read_meta
// calls with meta.json's text) returns metadata or throws hullpose::Error, for any bytes.
#include <cstdint>
#include <filesystem>

#include "fuzz_file.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)hullpose::parse_meta({reinterpret_cast<const char*>(data), size}, "fuzz.meta.json");
  } catch (const hullpose::Error&) {
  }
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  hullpose::DatasetMeta m;
  m.motion = "walk";
  m.frames = 120;
  m.seed = 18446744073709551615ull;
  m.start_utime = 1'700'000'000'000'000;
  m.stature_mm = 1750;
  m.camera_ids = {0, 1, 2, 7};
  m.noise = "drop=0.1,late=2";
  const auto p = std::filesystem::temp_directory_path() / "hullpose-fuzz-seed-meta.json";
  hullpose::write_meta(p, m);
  auto seed = hullpose::fuzz::read_all(p);
  std::filesystem::remove(p);
  return {seed};
}
