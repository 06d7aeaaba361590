#pragma once
// CK3's per-voxel decisions, shared verbatim by the CPU thinner (src/ck3.cpp) and the CUDA
// backend (fusion_host/gpu): one function per pass of an iteration (notes §2.6, §6). Each reads
// the voxel's code and flags and its neighbours' flags, and returns the voxel's new flags (or
// whether it is deleted); the backends only differ in how they store the volume and schedule
// the passes. Header-only, HULLPOSE_HD, no tables at namespace scope (device code cannot index
// host constexpr arrays): the tables come in a RuleTables the backend fills (make_rule_tables()
// on the host, a device copy on the GPU).
//
// Accessor concepts:
//   V: uint8_t flags(uint32_t idx) const; bool get(uint32_t idx) const;
//      int off27(int bit) const   (linear offset of the neighbour at code bit `bit`);
//      int face(int d) const      (linear offset of face direction d, order of kDirection*).
#include <cstdint>

#include "hullpose/thin/neighbourhood.hpp"
#include "hullpose/thin/rules.hpp"

#ifdef __CUDA_ARCH__
#define HULLPOSE_CTZ32(x) (__ffs(static_cast<int>(x)) - 1)
#define HULLPOSE_POPC32(x) __popc(x)
#else
#define HULLPOSE_CTZ32(x) __builtin_ctz(x)
#define HULLPOSE_POPC32(x) __builtin_popcount(x)
#endif

namespace hullpose::thin::ck3 {

// Per-voxel flags (one byte).
enum : uint8_t {
  kS0 = 1 << 0,     // simple and not in K (candidate before the curve rule)
  kSurfV = 1 << 1,  // non-simple with T̄ >= 2 (2D isthmus voxel)
  kK = 1 << 2,      // permanent constraint
  kSurf = 1 << 3,   // member of a 2-clique of candidates with T4̄ = 0 (Pink's "surface" pair)
  kS = 1 << 4,      // candidate (deletable unless marked)
  kZ2 = 1 << 5,     // marked at level 2
  kZ1 = 1 << 6,     // marked at level 1
  kInB = 1 << 7,    // in the border list
  // Isthmus found this iteration (joins K). Shares kSurf's bit: kSurf is used by the CK3 rule
  // only, kPK by the isthmus rule only, and one byte per voxel halves the footprint of the
  // neighbour reads that dominate the passes.
  kPK = kSurf,
};

// Per 9-bit ring grid (centre ignored): crucial 2-clique, 1D isthmus 2-clique, T4̄ = 0.
enum : uint8_t { kRingCrucial = 1, kRingIsthmus = 2, kRingFull4 = 4 };

struct RuleTables {
  const uint64_t* simple_lut = nullptr;  // 2^26 bits (simple_lut.hpp)
  const uint8_t* tbar_lut = nullptr;     // 2^18 entries: T̄ clamped to 2
  uint32_t n18_bytes[4][256] = {};       // code byte -> its bits of the compacted N18* index
  uint8_t ring[512] = {};
  uint32_t interior_mask[6] = {};  // face direction d: q = x + e and q's 4 face neighbours ⊥ e
  nb::Quadrant quadrants[4] = {};
  nb::Octant octants[8] = {};
  uint8_t plane_bit[3][9] = {};  // nb::kPlaneCells

  HULLPOSE_HD bool simple(uint32_t code) const {
    const uint32_t i = nb::lut_index(code);
    return (simple_lut[i >> 6] >> (i & 63) & 1u) != 0;
  }
  HULLPOSE_HD int tbar_class(uint32_t code) const {
    return tbar_lut[n18_bytes[0][code & 0xff] | n18_bytes[1][code >> 8 & 0xff] |
                    n18_bytes[2][code >> 16 & 0xff] | n18_bytes[3][code >> 24 & 0xff]];
  }
};

// Face direction d in D6I's order (notes §4.2): -z, +z, -y, +y, -x, +x.
HULLPOSE_HD constexpr int direction_axis(int d) {
  return 2 - d / 2;
}
HULLPOSE_HD constexpr int direction_sign(int d) {
  return (d & 1) ? 1 : -1;
}

// Members of a clique other than x, given as 27-bit code bits, all "free" (flags & mask == want)?
// Read lazily: most cliques of a border voxel contain an interior voxel, which fails at once.
template <class V>
HULLPOSE_HD bool members_free(const V& vol, uint32_t idx, uint32_t members, uint8_t mask,
                              uint8_t want) {
  for (uint32_t m = members & ~nb::kCentreBit; m != 0; m &= m - 1)
    if ((vol.flags(idx + static_cast<uint32_t>(vol.off27(HULLPOSE_CTZ32(m)))) & mask) != want)
      return false;
  return true;
}
HULLPOSE_HD inline uint32_t plane_members(const RuleTables& t, uint32_t cells, int axis) {
  uint32_t code = 0;
  for (uint32_t c = cells; c != 0; c &= c - 1) code |= 1u << t.plane_bit[axis][HULLPOSE_CTZ32(c)];
  return code;
}

// Pass 1: flags of a border voxel from its code alone.
HULLPOSE_HD inline uint8_t classify(const RuleTables& t, CurveRule rule, uint32_t code) {
  uint8_t f = kInB;
  const bool simple = t.simple(code);
  if (rule == CurveRule::kEndVoxel && HULLPOSE_POPC32(code & ~nb::kCentreBit) == 1) f |= kK;
  if (rule == CurveRule::kIsthmus && !simple && t.tbar_class(code) == 1 && nb::t26(code, 3) == 2)
    f |= kK;
  if (!(f & kK)) {
    if (simple) {
      f |= kS0;
      if (rule == CurveRule::kUltimate || rule == CurveRule::kEndVoxel) f |= kS;
    } else if (t.tbar_class(code) >= 2) {
      f |= kSurfV;
    }
  }
  return f;
}

// CK3 rule, pass 2a: surface 2-cliques (both voxels candidates, all four axial ring positions
// occupied) mark kSurf.
template <class V>
HULLPOSE_HD uint8_t ck3_surface(const V& vol, const RuleTables& t, uint32_t idx, uint32_t code,
                                uint8_t f) {
  if (!(f & kS0)) return f;
  for (int d = 0; d < 6; ++d)
    if ((vol.flags(idx + vol.face(d)) & kS0) &&
        (t.ring[nb::pair_ring(code, direction_axis(d), direction_sign(d))] & kRingFull4))
      return f | kSurf;
  return f;
}
// CK3 rule, pass 2b: residual voxels (no interior 6-neighbour) with no surface 26-neighbour are
// curve voxels, not deletable in this iteration (notes §3.3); the other candidates get kS.
template <class V>
HULLPOSE_HD uint8_t ck3_candidate(const V& vol, const RuleTables& t, uint32_t idx, uint32_t code,
                                  uint8_t f) {
  if (!(f & kS0)) return f;
  bool residual = true;
  for (int d = 0; d < 6 && residual; ++d) {
    const uint32_t m = t.interior_mask[d];
    if ((code & m) == m && vol.get(idx + 2 * vol.face(d))) residual = false;
  }
  // Only object neighbours can carry surface marks.
  const bool curve = residual && members_free(vol, idx, code, kSurf | kSurfV, 0);
  return curve ? f : static_cast<uint8_t>(f | kS);
}

// Isthmus rule, pass 2a: 2-clique isthmus (T4̄ != 0, T8 = 2) marks kPK; crucial 2-cliques of
// candidates mark kZ2 for the 1-clique step.
template <class V>
HULLPOSE_HD uint8_t isthmus_pairs(const V& vol, const RuleTables& t, uint32_t idx, uint32_t code,
                                  uint8_t f) {
  if (!(f & kS0)) return f;
  for (int d = 0; d < 6; ++d) {
    if (!(vol.flags(idx + vol.face(d)) & kS0)) continue;
    const uint8_t r = t.ring[nb::pair_ring(code, direction_axis(d), direction_sign(d))];
    if (r & kRingCrucial) f |= kZ2;
    if (r & kRingIsthmus) f |= kPK;
  }
  return f;
}
// Isthmus rule, pass 2b: 1-clique isthmus: candidates only, none marked at the 2-clique step,
// both caps non-empty.
template <class V>
HULLPOSE_HD uint8_t isthmus_edges(const V& vol, const RuleTables& t, uint32_t idx, uint32_t code,
                                  uint8_t f) {
  if ((f & (kS0 | kZ2)) != kS0) return f;
  for (int axis = 0; axis < 3; ++axis) {
    const uint32_t p0 = nb::plane9(code, axis, 0), lo = nb::plane9(code, axis, -1),
                   hi = nb::plane9(code, axis, 1);
    for (int qi = 0; qi < 4; ++qi) {
      const nb::Quadrant& q = t.quadrants[qi];
      if (nb::quadrant_has_diagonal(p0, q) && (lo & q.cells) && (hi & q.cells) &&
          members_free(vol, idx, plane_members(t, p0 & q.cells, axis), kS0 | kZ2, kS0))
        return f | kPK;
    }
  }
  return f;
}
// Isthmus rule, pass 2c: isthmuses join K for good; the other candidates go on, marks cleared.
HULLPOSE_HD inline uint8_t isthmus_settle(uint8_t f) {
  if (f & kPK) return kInB | kK;
  if (f & kS0) return static_cast<uint8_t>((f & ~kZ2) | kS);
  return f;
}

// Pass 3, level 2: crucial 2-cliques of two candidates.
template <class V>
HULLPOSE_HD uint8_t level2(const V& vol, const RuleTables& t, uint32_t idx, uint32_t code,
                           uint8_t f) {
  if (!(f & kS)) return f;
  for (int d = 0; d < 6; ++d)
    if ((vol.flags(idx + vol.face(d)) & kS) &&
        (t.ring[nb::pair_ring(code, direction_axis(d), direction_sign(d))] & kRingCrucial))
      return f | kZ2;
  return f;
}
// Pass 4, level 1: crucial 1-cliques of unmarked candidates (level-2 marks only).
template <class V>
HULLPOSE_HD uint8_t level1(const V& vol, const RuleTables& t, uint32_t idx, uint32_t code,
                           uint8_t f) {
  if ((f & (kS | kZ2)) != kS) return f;
  for (int axis = 0; axis < 3; ++axis) {
    const uint32_t p0 = nb::plane9(code, axis, 0), lo = nb::plane9(code, axis, -1),
                   hi = nb::plane9(code, axis, 1);
    for (int qi = 0; qi < 4; ++qi) {
      const nb::Quadrant& q = t.quadrants[qi];
      if (nb::quadrant_has_diagonal(p0, q) && nb::edge_crucial(lo, hi, q) &&
          members_free(vol, idx, plane_members(t, p0 & q.cells, axis), kS | kZ2, kS))
        return f | kZ1;
    }
  }
  return f;
}
// Pass 5, level 0: essential 0-cliques of unmarked candidates. True: the voxel is deleted.
template <class V>
HULLPOSE_HD bool level0_deletes(const V& vol, const RuleTables& t, uint32_t idx, uint32_t code,
                                uint8_t f, ZeroCliqueTest test) {
  if ((f & (kS | kZ2 | kZ1)) != kS) return false;
  for (int oi = 0; oi < 8; ++oi) {
    const nb::Octant& o = t.octants[oi];
    const uint32_t block = code & o.cells;
    if ((test == ZeroCliqueTest::kAntipodal ? nb::block_antipodal(block, o)
                                            : nb::block_spans3(block, o)) &&
        members_free(vol, idx, block, kS | kZ2 | kZ1, kS))
      return false;
  }
  return true;
}

}  // namespace hullpose::thin::ck3

namespace hullpose::thin::ck3 {
// The tables with the host LUTs (hullpose_thin). The CUDA backend copies it and swaps in device
// copies of the LUTs.
const RuleTables& host_rule_tables();
}  // namespace hullpose::thin::ck3
