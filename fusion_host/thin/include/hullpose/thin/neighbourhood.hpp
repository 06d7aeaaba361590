#pragma once
// Pure functions on 3x3x3 neighbourhood codes: the topological numbers of simple-point theory
// (26/6 adjacency) and the crucial-clique tests of critical-kernel thinning
// (../shared/reference/critical-kernels-thinning.md, "the notes"). Everything here is
// header-only, allocation-free and branch-light so that the CUDA backend (issue 8) can share it
// verbatim: mark new functions HULLPOSE_HD.
//
// Code layout (notes §0): bit (dz+1)*9 + (dy+1)*3 + (dx+1) of a 27-bit code is the voxel at
// offset (dx, dy, dz); the centre is bit 13.
#include <cstdint>

#include "hullpose/common/host_device.hpp"

namespace hullpose::thin::nb {

inline constexpr uint32_t kAll27 = (1u << 27) - 1;
inline constexpr int kCentre = 13;
inline constexpr uint32_t kCentreBit = 1u << kCentre;

HULLPOSE_HD constexpr int bit(int dx, int dy, int dz) {
  return (dz + 1) * 9 + (dy + 1) * 3 + (dx + 1);
}

// Positions by coordinate value along each axis (for the shift-based dilations below).
HULLPOSE_HD constexpr uint32_t plane_mask(int axis, int value) {
  uint32_t m = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int c = axis == 0 ? dx : axis == 1 ? dy : dz;
        if (c == value) m |= 1u << bit(dx, dy, dz);
      }
  return m;
}

// Face neighbours (6), and the 18-neighbourhood without the centre (faces + edges).
inline constexpr uint32_t kFaces = (1u << bit(-1, 0, 0)) | (1u << bit(1, 0, 0)) |
                                   (1u << bit(0, -1, 0)) | (1u << bit(0, 1, 0)) |
                                   (1u << bit(0, 0, -1)) | (1u << bit(0, 0, 1));
HULLPOSE_HD constexpr uint32_t n18_mask() {
  uint32_t m = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int n = (dx != 0) + (dy != 0) + (dz != 0);
        if (n == 1 || n == 2) m |= 1u << bit(dx, dy, dz);
      }
  return m;
}
inline constexpr uint32_t kN18 = n18_mask();

// One step of 6-adjacency and 26-adjacency dilation inside the 3x3x3 cube.
HULLPOSE_HD constexpr uint32_t shift_axis(uint32_t s, int axis) {
  const int step = axis == 0 ? 1 : axis == 1 ? 3 : 9;
  return ((s & ~plane_mask(axis, 1)) << step) | ((s & ~plane_mask(axis, -1)) >> step);
}
HULLPOSE_HD constexpr uint32_t dilate6(uint32_t s) {
  return (s | shift_axis(s, 0) | shift_axis(s, 1) | shift_axis(s, 2)) & kAll27;
}
HULLPOSE_HD constexpr uint32_t dilate26(uint32_t s) {
  s |= shift_axis(s, 0);
  s |= shift_axis(s, 1);
  s |= shift_axis(s, 2);
  return s & kAll27;
}

// The component of `set` that contains the lowest set bit of `seed` (seed must be in set).
template <bool k26>
HULLPOSE_HD constexpr uint32_t component(uint32_t set, uint32_t seed) {
  uint32_t comp = seed;
  for (;;) {
    const uint32_t next = (k26 ? dilate26(comp) : dilate6(comp)) & set;
    if (next == comp) return comp;
    comp = next;
  }
}

// T(x) = number of 26-components of X ∩ N26*(x) (notes §1.1). Counts up to `limit`.
HULLPOSE_HD constexpr int t26(uint32_t code, int limit = 27) {
  uint32_t set = code & kAll27 & ~kCentreBit;
  int n = 0;
  while (set != 0 && n < limit) {
    set &= ~component<true>(set, set & (0u - set));
    ++n;
  }
  return n;
}

// T̄(x) = number of 6-components of the background in N18*(x) that contain a face neighbour.
HULLPOSE_HD constexpr int t6bar(uint32_t code, int limit = 27) {
  uint32_t set = ~code & kN18;
  uint32_t faces = set & kFaces;
  int n = 0;
  while (faces != 0 && n < limit) {
    const uint32_t comp = component<false>(set, faces & (0u - faces));
    set &= ~comp;
    faces &= ~comp;
    ++n;
  }
  return n;
}

// Reference simple-point test by flood fill (the LUT in simple_lut.hpp is generated from this).
HULLPOSE_HD constexpr bool simple_reference(uint32_t code) {
  return t6bar(code, 2) == 1 && t26(code, 2) == 1;
}

// 26 neighbour bits without the centre: the index of the simple-point LUT.
HULLPOSE_HD constexpr uint32_t lut_index(uint32_t code) {
  return (code & 0x1fffu) | ((code >> 14 & 0x1fffu) << 13);
}
HULLPOSE_HD constexpr uint32_t code_from_index(uint32_t index) {
  return (index & 0x1fffu) | ((index >> 13 & 0x1fffu) << 14) | kCentreBit;
}
// The 18 N18* bits compacted (index of the T̄ table).
HULLPOSE_HD constexpr uint32_t n18_index(uint32_t code) {
  uint32_t idx = 0;
  int k = 0;
  for (int b = 0; b < 27; ++b)
    if (kN18 >> b & 1u) idx |= (code >> b & 1u) << k++;
  return idx;
}

// ---- planes through the centre ------------------------------------------------------------
// The 3x3 plane of a code at coordinate `value` along `axis`, as a 9-bit grid g = u + 3v with
// (u, v) = the two other axes in increasing order. Every test on planes below is invariant under
// the 8 symmetries of the square, so the orientation of (u, v) does not matter.
HULLPOSE_HD constexpr uint32_t plane9(uint32_t code, int axis, int value) {
  if (axis == 2) return code >> (9 * (value + 1)) & 0x1ffu;
  if (axis == 1) {
    const int o = 3 * (value + 1);
    return (code >> o & 7u) | (code >> (o + 9) & 7u) << 3 | (code >> (o + 18) & 7u) << 6;
  }
  // x: bits 3i + value + 1; squeeze each 9-bit chunk's bits 0, 3, 6 into bits 0, 1, 2.
  const uint32_t s = code >> (value + 1) & 0x1249249u;
  const uint32_t t = s | s >> 2 | s >> 4;
  return (t & 7u) | (t >> 6 & 0x38u) | (t >> 12 & 0x1c0u);
}
// Inverse of plane9 at value 0: the code bit of each of the 9 cells of the plane through x.
struct PlaneCells {
  int bit[3][9] = {};
  constexpr PlaneCells() {
    for (int b = 0; b < 27; ++b)
      for (int axis = 0; axis < 3; ++axis) {
        const int c = axis == 0 ? b % 3 : axis == 1 ? b / 3 % 3 : b / 9;
        if (c != 1) continue;
        const uint32_t g = plane9(1u << b, axis, 0);
        for (int i = 0; i < 9; ++i)
          if (g == (1u << i)) bit[axis][i] = b;
      }
  }
};
inline constexpr PlaneCells kPlaneCells;

// ---- 2-cliques (notes §2.2) --------------------------------------------------------------
// Ring of a 9-bit plane grid: the 8 cells around the centre in cyclic order; even = 4-neighbours.
inline constexpr int kRing[8] = {5, 8, 7, 6, 3, 0, 1, 2};  // +u, +u+v, +v, -u+v, -u, -u-v, -v, +u-v

// T8 of the set ring cells and T4̄ of the clear ones that contain a 4-neighbour position.
HULLPOSE_HD constexpr int ring_t8(uint32_t g) {
  // Components of set cells on the cycle, where two even (4-neighbour) cells two steps apart are
  // also adjacent (through the corner between them, in 8-adjacency).
  int w[8] = {};
  for (int i = 0; i < 8; ++i) w[i] = g >> kRing[i] & 1u;
  int parent[8] = {0, 1, 2, 3, 4, 5, 6, 7};
  auto find = [&](int a) {
    while (parent[a] != a) a = parent[a];
    return a;
  };
  for (int i = 0; i < 8; ++i) {
    const int j = (i + 1) % 8;
    if (w[i] && w[j]) parent[find(i)] = find(j);
    if (i % 2 == 0 && w[i] && w[(i + 2) % 8]) parent[find(i)] = find((i + 2) % 8);
  }
  int n = 0;
  for (int i = 0; i < 8; ++i) n += w[i] && find(i) == i;
  return n;
}
HULLPOSE_HD constexpr int ring_t4bar(uint32_t g) {
  int w[8] = {};
  for (int i = 0; i < 8; ++i) w[i] = g >> kRing[i] & 1u;
  int n = 0;
  // Runs of clear cells on the cycle (consecutive only) containing an even position.
  bool all_clear = true;
  for (int i = 0; i < 8; ++i) all_clear = all_clear && !w[i];
  if (all_clear) return 1;
  int start = 0;
  while (!w[start]) ++start;  // begin just after a set cell so runs do not wrap
  for (int k = 1; k <= 8; ++k) {
    const int i = (start + k) % 8;
    if (w[i]) continue;
    const int prev = (i + 7) % 8;
    if (!w[prev]) continue;  // not the start of a run
    bool has_even = false;
    for (int j = i; !w[j]; j = (j + 1) % 8) has_even = has_even || j % 2 == 0;
    n += has_even;
  }
  return n;
}
// Crucial 2-clique ⇔ NOT(T8 = 1 AND T4̄ = 1) over the projected ring (centre ignored).
HULLPOSE_HD constexpr bool ring_crucial(uint32_t g) {
  return !(ring_t8(g) == 1 && ring_t4bar(g) == 1);
}

// The ring of the 2-clique {x, x + e} with e = sign * unit(axis): the two planes OR'ed.
HULLPOSE_HD constexpr uint32_t pair_ring(uint32_t code, int axis, int sign) {
  return (plane9(code, axis, 0) | plane9(code, axis, sign)) & ~0x10u;
}
// All four 4-neighbour ring positions occupied (T4̄ = 0): Pink's "surface" 2-clique.
HULLPOSE_HD constexpr bool ring_full4(uint32_t g) {
  return (g & 0xaau) == 0xaau;
}

// ---- 1-cliques (notes §2.3) ---------------------------------------------------------------
// The four 2x2 quadrants of a plane grid that contain the centre cell (4), and in each the
// corner cell diagonal to the centre and the two others.
struct Quadrant {
  uint32_t cells, corner, side_a, side_b;
};
inline constexpr Quadrant kQuadrants[4] = {
    {0x1bu, 1u << 0, 1u << 1, 1u << 3},
    {0x36u, 1u << 2, 1u << 1, 1u << 5},
    {0xd8u, 1u << 6, 1u << 3, 1u << 7},
    {0x1b0u, 1u << 8, 1u << 5, 1u << 7},
};
// P ∩ X holds a diagonal pair (the centre is in X): the opposite corner, or both sides.
HULLPOSE_HD constexpr bool quadrant_has_diagonal(uint32_t plane, const Quadrant& q) {
  return (plane & q.corner) != 0 || ((plane & q.side_a) != 0 && (plane & q.side_b) != 0);
}
// Crucial ⇔ both caps empty or both non-empty.
HULLPOSE_HD constexpr bool edge_crucial(uint32_t cap_lo, uint32_t cap_hi, const Quadrant& q) {
  return ((cap_lo & q.cells) == 0) == ((cap_hi & q.cells) == 0);
}

// ---- 0-cliques (notes §2.4) ---------------------------------------------------------------
// The 8 2x2x2 blocks containing the centre, as 27-bit masks, and for each axis the layer of the
// block that does not contain the centre.
struct Octant {
  uint32_t cells;
  uint32_t far[3];
  uint32_t antipodal[4][2];  // the 4 antipodal pairs of the block (for the Pink/DGtal test)
};
HULLPOSE_HD constexpr Octant make_octant(int sx, int sy, int sz) {
  Octant o{};
  for (int dz = 0; dz <= 1; ++dz)
    for (int dy = 0; dy <= 1; ++dy)
      for (int dx = 0; dx <= 1; ++dx) {
        const uint32_t b = 1u << bit(dx * sx, dy * sy, dz * sz);
        o.cells |= b;
        if (dx) o.far[0] |= b;
        if (dy) o.far[1] |= b;
        if (dz) o.far[2] |= b;
      }
  int k = 0;
  for (int dz = 0; dz <= 1; ++dz)
    for (int dy = 0; dy <= 1; ++dy) {
      o.antipodal[k][0] = 1u << bit(0, dy * sy, dz * sz);
      o.antipodal[k][1] = 1u << bit(sx, (1 - dy) * sy, (1 - dz) * sz);
      ++k;
    }
  return o;
}
inline constexpr Octant kOctants[8] = {
    make_octant(-1, -1, -1), make_octant(1, -1, -1), make_octant(-1, 1, -1), make_octant(1, 1, -1),
    make_octant(-1, -1, 1),  make_octant(1, -1, 1),  make_octant(-1, 1, 1),  make_octant(1, 1, 1)};
// Corrected test (notes §2.4): Q ∩ X spans all three axes. `block` = code & o.cells (has centre).
HULLPOSE_HD constexpr bool block_spans3(uint32_t block, const Octant& o) {
  return (block & o.far[0]) != 0 && (block & o.far[1]) != 0 && (block & o.far[2]) != 0;
}
// Pink/DGtal test: the block holds an antipodal pair (misses cases; debug comparison only).
HULLPOSE_HD constexpr bool block_antipodal(uint32_t block, const Octant& o) {
  for (const auto& pair : o.antipodal)
    if ((block & pair[0]) != 0 && (block & pair[1]) != 0) return true;
  return false;
}

}  // namespace hullpose::thin::nb
