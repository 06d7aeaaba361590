// Writes a fuzz target's hullpose_fuzz_seeds() into a corpus directory: seed_0, seed_1, ...
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds();

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  int i = 0;
  for (const auto& seed : hullpose_fuzz_seeds()) {
    std::ofstream out(std::string(argv[1]) + "/seed_" + std::to_string(i++), std::ios::binary);
    out.write(reinterpret_cast<const char*>(seed.data()),
              static_cast<std::streamsize>(seed.size()));
  }
  return 0;
}
