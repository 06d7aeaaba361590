#pragma once
// Small tables shared by the thinners (internal to hullpose_thin).
#include <array>
#include <cstdint>

#include "hullpose/thin/ck3_rules.hpp"
#include "hullpose/thin/neighbourhood.hpp"

namespace hullpose::thin::detail {

struct Direction {
  int axis, sign;
};
// Face directions in D6I's order (notes §4.2): -z, +z, -y, +y, -x, +x.
inline constexpr Direction kDirections[6] = {{2, -1}, {2, 1}, {1, -1}, {1, 1}, {0, -1}, {0, 1}};

constexpr uint32_t offset_bit(int axis, int a, int u_axis, int u, int v_axis, int v) {
  int d[3] = {0, 0, 0};
  d[axis] = a;
  d[u_axis] = u;
  d[v_axis] = v;
  return 1u << nb::bit(d[0], d[1], d[2]);
}
// For direction d: the face neighbour q = x + e and q's four face neighbours orthogonal to e
// (all inside N26(x)). q is interior iff these five and x + 2e are object (x itself is).
constexpr std::array<uint32_t, 6> make_interior_masks() {
  std::array<uint32_t, 6> m{};
  for (int d = 0; d < 6; ++d) {
    const int a = kDirections[d].axis, s = kDirections[d].sign;
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    m[d] = offset_bit(a, s, u, 0, v, 0) | offset_bit(a, s, u, 1, v, 0) |
           offset_bit(a, s, u, -1, v, 0) | offset_bit(a, s, u, 0, v, 1) |
           offset_bit(a, s, u, 0, v, -1);
  }
  return m;
}
inline constexpr std::array<uint32_t, 6> kInteriorMask = make_interior_masks();

// Per 9-bit ring grid (centre ignored): ck3::kRingCrucial, kRingIsthmus, kRingFull4.
struct RingTables {
  std::array<uint8_t, 512> bits{};
  constexpr RingTables() {
    for (uint32_t g = 0; g < 512; ++g) {
      const uint32_t r = g & ~0x10u;
      const int t8 = nb::ring_t8(r), t4b = nb::ring_t4bar(r);
      bits[g] = static_cast<uint8_t>((!(t8 == 1 && t4b == 1) ? ck3::kRingCrucial : 0) |
                                     (t4b != 0 && t8 == 2 ? ck3::kRingIsthmus : 0) |
                                     (t4b == 0 ? ck3::kRingFull4 : 0));
    }
  }
};
inline constexpr RingTables kRingTables;

}  // namespace hullpose::thin::detail
