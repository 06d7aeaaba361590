// Fuzz target: the rig file reader (common/rig.hpp load_rig) returns a valid rig or throws
// hullpose::Error, for any bytes.
#include <cstdint>
#include <filesystem>

#include "../rig/rig_fixtures.hpp"
#include "fuzz_file.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/rig.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = hullpose::fuzz::input_file(data, size, ".rig.yaml");
  try {
    const hullpose::Rig rig = hullpose::load_rig(path);
    rig.validate();  // what load_rig returns is valid
  } catch (const hullpose::Error&) {
  }
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  std::vector<std::vector<uint8_t>> seeds;
  for (const int n : {1, 3}) {
    const auto p = std::filesystem::temp_directory_path() /
                   ("hullpose-fuzz-seed-rig" + std::to_string(n) + ".yaml");
    hullpose::save_rig(hullpose::testing::make_rig(n), p);
    seeds.push_back(hullpose::fuzz::read_all(p));
    std::filesystem::remove(p);
  }
  return seeds;
}
