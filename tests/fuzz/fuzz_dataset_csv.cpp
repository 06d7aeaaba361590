// Fuzz target: the dataset CSV readers (common/dataset.hpp parse_ground_truth and
// parse_estimates, which the read_* functions call with the file's text; the first byte picks
// which) return records or throw hullpose::Error, for any bytes.
#include <cstdint>
#include <filesystem>

#include "fuzz_file.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text = hullpose::fuzz::text(data + 1, size - 1);
  try {
    if (data[0] & 1)
      (void)hullpose::parse_estimates(text, "fuzz.csv");
    else
      (void)hullpose::parse_ground_truth(text, "fuzz.csv");
  } catch (const hullpose::Error&) {
  }
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  std::vector<hullpose::PoseRecord> frames(2);
  for (int f = 0; f < 2; ++f) {
    frames[f].frame = f;
    frames[f].utime = 1'700'000'000'000'000 + f * 33'333;
    frames[f].valid = f == 0;
    frames[f].reason = f == 0 ? 0 : 4;
    for (int j = 0; j < hullpose::kNumJoints; ++j)
      frames[f].joints[j] = {j * 10.0 + f, -j * 3.5, 1000.25};
  }
  const auto dir = std::filesystem::temp_directory_path();
  hullpose::write_ground_truth(dir / "hullpose-fuzz-seed-gt.csv", frames);
  {
    hullpose::EstimateWriter w(dir / "hullpose-fuzz-seed-est.csv");
    for (const auto& r : frames) w.write(r);
  }
  auto gt = hullpose::fuzz::read_all(dir / "hullpose-fuzz-seed-gt.csv");
  auto est = hullpose::fuzz::read_all(dir / "hullpose-fuzz-seed-est.csv");
  gt.insert(gt.begin(), 0);
  est.insert(est.begin(), 1);
  std::filesystem::remove(dir / "hullpose-fuzz-seed-gt.csv");
  std::filesystem::remove(dir / "hullpose-fuzz-seed-est.csv");
  return {gt, est};
}
