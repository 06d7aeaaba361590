// Build-time generator of the topology tables embedded in hullpose_thin (see simple_lut.cpp):
//   bytes [0, 8 MiB):        simple-point LUT, bit i of 64-bit word i/64 =
//   simple(code_from_index(i)) bytes [8 MiB, +256 KiB): T̄ of every N18* configuration, clamped to 2
//   (one byte each)
// Run once per build tree instead of at every process start (the flood fill takes seconds).
// Usage: hullpose_thin_lutgen OUT.bin
#include <cstdint>
#include <cstdio>
#include <thread>
#include <vector>

#include "hullpose/thin/neighbourhood.hpp"

namespace nb = hullpose::thin::nb;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.bin\n", argv[0]);
    return 2;
  }
  // T̄ depends on the 18 N18* bits only: tabulate it first, then the simple test needs one
  // 26-flood fill (T == 1 ⇔ the component of the lowest bit is everything) only where T̄ == 1.
  std::vector<uint8_t> tbar(1u << 18);
  std::vector<uint32_t> n18_bits;
  for (int b = 0; b < 27; ++b)
    if (nb::kN18 >> b & 1u) n18_bits.push_back(1u << b);
  for (uint32_t i = 0; i < tbar.size(); ++i) {
    uint32_t code = 0;
    for (size_t k = 0; k < n18_bits.size(); ++k)
      if (i >> k & 1u) code |= n18_bits[k];
    tbar[i] = static_cast<uint8_t>(nb::t6bar(code, 2));
  }
  // For the N18 index of a code, tabulate per byte of the 27-bit code (4 bytes).
  std::vector<uint32_t> n18_of_byte(4 * 256);
  for (int byte = 0; byte < 4; ++byte)
    for (uint32_t v = 0; v < 256; ++v) n18_of_byte[byte * 256 + v] = nb::n18_index(v << (8 * byte));

  constexpr uint32_t kWords = (1u << 26) / 64;
  std::vector<uint64_t> lut(kWords);
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (uint32_t w = t; w < kWords; w += threads) {
        uint64_t bits = 0;
        for (uint32_t j = 0; j < 64; ++j) {
          const uint32_t code = nb::code_from_index(w * 64 + j);
          const uint32_t n18 = n18_of_byte[code & 0xff] | n18_of_byte[256 + (code >> 8 & 0xff)] |
                               n18_of_byte[512 + (code >> 16 & 0xff)] |
                               n18_of_byte[768 + (code >> 24)];
          if (tbar[n18] != 1) continue;
          const uint32_t set = code & ~nb::kCentreBit;
          if (set != 0 && nb::component<true>(set, set & (0u - set)) == set)
            bits |= uint64_t{1} << j;
        }
        lut[w] = bits;
      }
    });
  for (auto& th : pool) th.join();

  std::FILE* f = std::fopen(argv[1], "wb");
  if (!f) {
    std::fprintf(stderr, "%s: cannot write %s\n", argv[0], argv[1]);
    return 1;
  }
  const bool ok = std::fwrite(lut.data(), sizeof(uint64_t), lut.size(), f) == lut.size() &&
                  std::fwrite(tbar.data(), 1, tbar.size(), f) == tbar.size();
  if (std::fclose(f) != 0 || !ok) {
    std::fprintf(stderr, "%s: write failed: %s\n", argv[0], argv[1]);
    return 1;
  }
  return 0;
}
