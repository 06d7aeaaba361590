// Runs a fuzz target as a plain unit test: seeded random byte strings plus mutations of the
// target's own valid seeds (hullpose_fuzz_seeds), so the normal and sanitizer test runs
// exercise it without libFuzzer.
#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds();

TEST_CASE("fuzz target survives seeded random and mutated inputs") {
  std::mt19937 rng(12345);
  std::vector<uint8_t> buf;
  for (int i = 0; i < 20000; ++i) {
    buf.resize(rng() % 64);
    for (auto& b : buf) b = static_cast<uint8_t>(rng());
    REQUIRE(LLVMFuzzerTestOneInput(buf.data(), buf.size()) == 0);
  }
  const auto seeds = hullpose_fuzz_seeds();
  REQUIRE_FALSE(seeds.empty());
  for (const auto& seed : seeds) {
    REQUIRE(LLVMFuzzerTestOneInput(seed.data(), seed.size()) == 0);
    for (int i = 0; i < 20000; ++i) {
      buf = seed;
      const int flips = 1 + static_cast<int>(rng() % 4);
      for (int f = 0; f < flips && !buf.empty(); ++f)
        buf[rng() % buf.size()] = static_cast<uint8_t>(rng());
      if (rng() % 4 == 0) buf.resize(rng() % (buf.size() + 1));
      REQUIRE(LLVMFuzzerTestOneInput(buf.data(), buf.size()) == 0);
    }
  }
}
