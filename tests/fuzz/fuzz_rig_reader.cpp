// Fuzz target: the rig file reader (common/rig.hpp parse_rig, which load_rig calls with the
// file's text) returns a valid rig or throws hullpose::Error, for any bytes.
#include <cstdint>
#include <filesystem>

#include "../rig/rig_fixtures.hpp"
#include "fuzz_file.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/rig.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  hullpose::fuzz::quiet_logs();
  try {
    const hullpose::Rig rig =
        hullpose::parse_rig(hullpose::fuzz::text(data, size), "fuzz.rig.yaml");
    rig.validate();  // what parse_rig returns is valid
  } catch (const hullpose::Error&) {
  }
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  // The whole format in few bytes (flow style, two cameras, a rotation to be repaired), within
  // the target's -max_len; then what save_rig writes.
  std::vector<std::vector<uint8_t>> seeds = {hullpose::fuzz::bytes_of(
      "version: 1\nrig_id: rigA\nunits: mm\n"
      "capture_volume: {min_mm: [-1000, -1000, 0], max_mm: [1000, 1000, 2000]}\ncameras:\n"
      "  - {id: 0, name: cam0, width: 64, height: 48, fx: 50, fy: 50, cx: 32, cy: 24,\n"
      "     dist: [0, 0, 0, 0, 0], R: [1, 0, 0, 0, 1, 0, 0, 0, 1], t_mm: [0, 0, 3000]}\n"
      "  - {id: 1, width: 64, height: 48, fx: 50, fy: 50, cx: 32, cy: 24,\n"
      "     dist: [0.1, 0, 0, 0, 0], R: [1, 0, 0, 0, 1.0001, 0, 0, 0, 1], t_mm: [0, 0, 3000]}\n")};
  for (const int n : {1, 3}) {
    const auto p = std::filesystem::temp_directory_path() /
                   ("hullpose-fuzz-seed-rig" + std::to_string(n) + ".yaml");
    hullpose::save_rig(hullpose::testing::make_rig(n), p);
    seeds.push_back(hullpose::fuzz::read_all(p));
    std::filesystem::remove(p);
  }
  return seeds;
}
