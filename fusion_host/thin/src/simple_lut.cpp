// Embeds the generated tables (HULLPOSE_THIN_LUT_FILE, written by hullpose_thin_lutgen at build
// time) into .rodata with the assembler's .incbin: no 40 MB C array to compile, no file to find
// at run time.
#include "hullpose/thin/simple_lut.hpp"

#include <array>

#ifndef HULLPOSE_THIN_LUT_FILE
#error "HULLPOSE_THIN_LUT_FILE must name the generated table file"
#endif

__asm__(
    ".section .rodata\n"
    ".balign 64\n"
    ".global hullpose_simple_lut\n"
    ".type hullpose_simple_lut, @object\n"
    ".size hullpose_simple_lut, 8388608\n"
    ".global hullpose_tbar_lut\n"
    ".type hullpose_tbar_lut, @object\n"
    ".size hullpose_tbar_lut, 262144\n"
    "hullpose_simple_lut:\n"
    ".incbin \"" HULLPOSE_THIN_LUT_FILE
    "\", 0, 8388608\n"
    "hullpose_tbar_lut:\n"
    ".incbin \"" HULLPOSE_THIN_LUT_FILE
    "\", 8388608, 262144\n"
    ".previous\n");

namespace hullpose::thin {

namespace {
struct N18Bytes {
  std::array<uint32_t, 4 * 256> v{};
  constexpr N18Bytes() {
    for (int byte = 0; byte < 4; ++byte)
      for (uint32_t x = 0; x < 256; ++x) v[byte * 256 + x] = nb::n18_index(x << (8 * byte));
  }
};
constexpr N18Bytes kN18Bytes;
}  // namespace

uint32_t n18_index_fast(uint32_t code) {
  const auto& t = kN18Bytes.v;
  return t[code & 0xff] | t[256 + (code >> 8 & 0xff)] | t[512 + (code >> 16 & 0xff)] |
         t[768 + (code >> 24 & 0xff)];
}

}  // namespace hullpose::thin
