#pragma once
// Tables generated at build time (src/lut_gen.cpp) and linked into hullpose_thin, so that no
// process pays the generation at start-up:
//  - simple-point LUT over the 26 neighbour bits, 1 bit per configuration (8 MiB);
//  - T̄ (clamped to 2) of every N18* configuration (256 KiB).
// They equal nb::simple_reference / nb::t6bar by construction; tests/fusion/test_neighbourhood
// checks them (including the 25,985,144 simple configurations of notes §1.2).
#include <cstdint>

#include "hullpose/thin/neighbourhood.hpp"

extern "C" {
extern const uint64_t hullpose_simple_lut[(1u << 26) / 64];
extern const uint8_t hullpose_tbar_lut[1u << 18];
}

namespace hullpose::thin {

inline bool is_simple(uint32_t code) {
  const uint32_t i = nb::lut_index(code);
  return (hullpose_simple_lut[i >> 6] >> (i & 63) & 1u) != 0;
}

// Starts loading the LUT word of `code` (is_simple's only cache miss) ahead of its use.
inline void prefetch_simple(uint32_t code) {
  __builtin_prefetch(&hullpose_simple_lut[nb::lut_index(code) >> 6]);
}

// The N18* bits of a code compacted to 18 bits, by table (4 byte lookups).
uint32_t n18_index_fast(uint32_t code);

// T̄(x) clamped to 2: 0 = interior, 1 = one background component, 2 = two or more (2D isthmus).
inline int tbar_class(uint32_t code) {
  return hullpose_tbar_lut[n18_index_fast(code)];
}

}  // namespace hullpose::thin
