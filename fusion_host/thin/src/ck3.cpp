// CK3: one iteration = barrier-separated parallel passes over the border list (notes §2.6, §6):
//   classify (simple / 2D-isthmus / constraint) -> curve rule -> level 2 -> level 1 -> level 0,
//   then a serial pass applies the deletions and grows the border list.
// Each pass reads only what earlier passes wrote and writes only the flags of the voxel it
// evaluates ("voxel-centric", notes §2.7), which makes the marking level-parallel, symmetric and
// independent of thread count and order. The flags a pass reads from neighbours live in bit
// planes laid out like the object (PaddedVolume::plane_code), so a clique's "all members free"
// is one mask test on a gathered code, not a byte read and a branch per member; the decisions
// are ck3_rules.hpp's (shared with the CUDA backend) and tested equal to them.
#include <omp.h>

#include <algorithm>
#include <bit>

#include "hullpose/thin/ck3_rules.hpp"
#include "hullpose/thin/simple_lut.hpp"
#include "hullpose/thin/thinning.hpp"
#include "padded_volume.hpp"
#include "ring_tables.hpp"

namespace hullpose::thin {

namespace {

using namespace ck3;

}  // namespace

const char* to_string(CurveRule rule) {
  switch (rule) {
    case CurveRule::kUltimate:
      return "ultimate";
    case CurveRule::kCk3:
      return "ck3";
    case CurveRule::kIsthmus:
      return "isthmus";
    case CurveRule::kEndVoxel:
      return "end";
  }
  return "?";
}

namespace {

// The nine 3x3 planes of a code (nb::plane9, axis-major, values -1, 0, 1): the 2- and 1-clique
// tests of three passes read them, so a candidate computes them once per iteration.
struct Planes {
  uint16_t p[3][3];
  explicit Planes(uint32_t code = 0) {
    for (int a = 0; a < 3; ++a)
      for (int v = 0; v < 3; ++v) p[a][v] = static_cast<uint16_t>(nb::plane9(code, a, v - 1));
  }
  // nb::pair_ring.
  uint32_t ring(int axis, int sign) const { return (p[axis][1] | p[axis][1 + sign]) & ~0x10u; }
};

}  // namespace

struct Ck3Thinner::State {
  detail::PaddedVolume vol;
  std::vector<uint32_t> border, next_border, codes, k_list;
  // Flags of border-list entry i (the volume's byte flags hold only kInB / kK; neighbours'
  // pass flags are read from the bit planes).
  std::vector<uint8_t> own;
  std::vector<Planes> planes;                  // of candidates (kS0), set by the classify pass
  std::vector<std::vector<uint32_t>> deleted;  // per thread: border-list positions
  int face_off[6] = {};
};

Ck3Thinner::Ck3Thinner(const ThinOptions& options)
    : options_(options), state_(std::make_unique<State>()) {}
Ck3Thinner::~Ck3Thinner() = default;

namespace {

// Bit planes of the neighbour flags the passes read (PaddedVolume::plane_code). Each pass reads
// planes that earlier passes wrote and writes one no pass reads before the next barrier, so a
// pass never sees its own writes (level-parallel marking, as with the byte flags the CUDA
// backend keeps).
enum Plane : int {
  kPlaneS0,    // kS0: simple, not in K
  kPlaneMark,  // CK3: kSurf | kSurfV; isthmus rule: kS0 and not kZ2 (free for the 1-clique step)
  kPlaneS,     // kS: candidate
  kPlaneF1,    // kS and not kZ2: free at level 1
  kPlaneF0,    // kS and not kZ2, kZ1: free at level 0
};

// The per-voxel rules of ck3_rules.hpp with every "neighbour flags" read replaced by a bit test
// on a gathered plane code; the results are equal by construction and tested equal
// (test_fusion_thinning_rules). Where all members of a clique must be free, an empty free code
// (no free neighbour at all: common on real hulls' one-voxel bumps) answers at once.
struct MaskRules {
  const RuleTables& t;
  uint32_t face_bit[6];
  uint32_t plane_code[3][512];  // nb::kPlaneCells of a 9-bit plane grid, as code bits

  explicit MaskRules(const RuleTables& tables) : t(tables) {
    for (int d = 0; d < 6; ++d) {
      int e[3] = {0, 0, 0};
      e[direction_axis(d)] = direction_sign(d);
      face_bit[d] = 1u << nb::bit(e[0], e[1], e[2]);
    }
    for (int a = 0; a < 3; ++a)
      for (uint32_t g = 0; g < 512; ++g)
        plane_code[a][g] = plane_members(t, g, a) & ~nb::kCentreBit;
  }

  // Any face neighbour in `nbrs` whose 2-clique ring has property `bit`?
  bool face_ring(const Planes& pl, uint32_t nbrs, uint8_t bit) const {
    if ((nbrs & nb::kFaces) == 0) return false;
    for (int d = 0; d < 6; ++d)
      if ((nbrs & face_bit[d]) && (t.ring[pl.ring(direction_axis(d), direction_sign(d))] & bit))
        return true;
    return false;
  }
  // A 1-clique (plane quadrant with a diagonal pair) with all members in `free`, whose caps pass
  // `caps(lo, hi, q)`.
  template <class Caps>
  bool free_edge(const Planes& pl, uint32_t free, Caps&& caps) const {
    if ((free & ~nb::kCentreBit) == 0) return false;
    for (int axis = 0; axis < 3; ++axis) {
      const uint32_t lo = pl.p[axis][0], p0 = pl.p[axis][1], hi = pl.p[axis][2];
      for (int qi = 0; qi < 4; ++qi) {
        const nb::Quadrant& q = t.quadrants[qi];
        if (nb::quadrant_has_diagonal(p0, q) && caps(lo, hi, q) &&
            (plane_code[axis][p0 & q.cells] & ~free) == 0)
          return true;
      }
    }
    return false;
  }
  // level0_deletes with the free (kS, unmarked) neighbours as a code.
  bool deletes(uint32_t code, uint32_t free, ZeroCliqueTest test) const {
    if ((free & ~nb::kCentreBit) == 0) return true;
    for (int oi = 0; oi < 8; ++oi) {
      const nb::Octant& o = t.octants[oi];
      const uint32_t block = code & o.cells;
      if ((test == ZeroCliqueTest::kAntipodal ? nb::block_antipodal(block, o)
                                              : nb::block_spans3(block, o)) &&
          (block & ~nb::kCentreBit & ~free) == 0)
        return false;
    }
    return true;
  }
};

}  // namespace

ThinStats Ck3Thinner::thin(fusion::BitGrid& volume, fusion::BitGrid* constraint) {
  State& s = *state_;
  detail::PaddedVolume& vol = s.vol;
  ThinStats stats;
  vol.load(volume, constraint, kK, kInB, s.border, s.k_list);
  stats.initial_voxels = vol.voxels();
  size_t removed_total = 0;
  for (int d = 0; d < 6; ++d) {
    const auto& [axis, sign] = detail::kDirections[d];
    s.face_off[d] = vol.offset(axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0);
  }
  const int threads = std::max(1, options_.threads);
  s.deleted.resize(static_cast<size_t>(threads));
  const CurveRule rule = options_.rule;
  const ZeroCliqueTest zero = options_.zero_clique;
  const RuleTables& tables = host_rule_tables();
  static const MaskRules rules(tables);
  int iterations = 0;

  while (!s.border.empty()) {
    const std::vector<uint32_t>& border = s.border;
    const size_t n = border.size();
    s.codes.resize(n);
    s.own.resize(n);
    s.planes.resize(n);
    stats.visited += n;
    const bool parallel =
        threads > 1 && n >= static_cast<size_t>(std::max(0, options_.min_parallel_border));

    // The passes, as orphaned worksharing loops: run by every thread of a team, or directly by
    // this thread when the iteration is too small to share (no OpenMP team set up at all).
    auto passes = [&] {
      const int tid = omp_get_thread_num();
      // Each pass: the voxel's new flags from its own, its code and (through `out`) the bit it
      // sets in plane `out_plane`.
      auto pass = [&](int out_plane, auto&& rule_fn) {
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
          bool out = false;
          s.own[i] = rule_fn(border[i], s.codes[i], s.planes[i], s.own[i], out);
          if (out) vol.plane_set(out_plane, border[i], parallel);
        }
      };
      // 1. Codes first, prefetching each one's word of the 8 MiB simple-point LUT, whose misses
      // otherwise dominate the classification. Same static schedule as the next loop, so each
      // thread reads back only codes it wrote (no barrier needed).
#pragma omp for schedule(static) nowait
      for (size_t i = 0; i < n; ++i) {
        const uint32_t code = vol.code(border[i]);
        s.codes[i] = code;
        prefetch_simple(code);
      }
#pragma omp for schedule(static)
      for (size_t i = 0; i < n; ++i) {
        const uint8_t f = classify(tables, rule, s.codes[i]);
        s.own[i] = f;
        if (f & kS0) s.planes[i] = Planes(s.codes[i]);
        if (f & kS0) vol.plane_set(kPlaneS0, border[i], parallel);
        if (f & kS) vol.plane_set(kPlaneS, border[i], parallel);
        if (rule == CurveRule::kCk3 && (f & kSurfV)) vol.plane_set(kPlaneMark, border[i], parallel);
      }

      // 2. Curve rule.
      if (rule == CurveRule::kCk3) {
        // Surface 2-cliques (ck3_surface), then residual voxels without a surface neighbour stay
        // (ck3_candidate).
        pass(kPlaneMark, [&](uint32_t idx, uint32_t, const Planes& pl, uint8_t f, bool& out) {
          if (!(f & kS0) || !rules.face_ring(pl, vol.plane_code(kPlaneS0, idx), kRingFull4))
            return f;
          out = true;
          return static_cast<uint8_t>(f | kSurf);
        });
        pass(kPlaneS, [&](uint32_t idx, uint32_t code, const Planes&, uint8_t f, bool& out) {
          if (!(f & kS0)) return f;
          bool residual = true;
          for (int d = 0; d < 6 && residual; ++d) {
            const uint32_t m = tables.interior_mask[d];
            if ((code & m) == m && vol.get(idx + 2 * static_cast<uint32_t>(s.face_off[d])))
              residual = false;
          }
          if (residual && (vol.plane_code(kPlaneMark, idx) & code & ~nb::kCentreBit) == 0) return f;
          out = true;
          return static_cast<uint8_t>(f | kS);
        });
      } else if (rule == CurveRule::kIsthmus) {
        pass(kPlaneMark, [&](uint32_t idx, uint32_t, const Planes& pl, uint8_t f, bool& out) {
          if (!(f & kS0)) return f;
          const uint32_t nbrs = vol.plane_code(kPlaneS0, idx);
          if (rules.face_ring(pl, nbrs, kRingCrucial)) f |= kZ2;
          if (rules.face_ring(pl, nbrs, kRingIsthmus)) f |= kPK;
          out = !(f & kZ2);
          return f;
        });
        pass(kPlaneS, [&](uint32_t idx, uint32_t, const Planes& pl, uint8_t f, bool& out) {
          if ((f & (kS0 | kZ2)) == kS0 &&
              rules.free_edge(pl, vol.plane_code(kPlaneMark, idx),
                              [](uint32_t lo, uint32_t hi, const nb::Quadrant& q) {
                                return (lo & q.cells) && (hi & q.cells);
                              }))
            f |= kPK;
          f = isthmus_settle(f);
          out = (f & kS) != 0;
          return f;
        });
      }
      // 3.-4. Levels 2 and 1.
      pass(kPlaneF1, [&](uint32_t idx, uint32_t, const Planes& pl, uint8_t f, bool& out) {
        if (!(f & kS)) return f;
        if (rules.face_ring(pl, vol.plane_code(kPlaneS, idx), kRingCrucial))
          return static_cast<uint8_t>(f | kZ2);
        out = true;
        return f;
      });
      pass(kPlaneF0, [&](uint32_t idx, uint32_t, const Planes& pl, uint8_t f, bool& out) {
        if ((f & (kS | kZ2)) != kS) return f;
        if (rules.free_edge(pl, vol.plane_code(kPlaneF1, idx), nb::edge_crucial))
          return static_cast<uint8_t>(f | kZ1);
        out = true;
        return f;
      });
      // 5. Level 0: what stays unmarked is deleted.
      std::vector<uint32_t>& deleted = s.deleted[static_cast<size_t>(tid)];
#pragma omp for schedule(static)
      for (size_t i = 0; i < n; ++i)
        if ((s.own[i] & (kS | kZ2 | kZ1)) == kS &&
            rules.deletes(s.codes[i], vol.plane_code(kPlaneF0, border[i]), zero))
          deleted.push_back(static_cast<uint32_t>(i));
    };
    if (parallel) {
#pragma omp parallel num_threads(threads)
      passes();
    } else {
      passes();
    }

    // 6. Delete, grow the border list with newly exposed voxels, move K out of it.
    size_t removed = 0, constrained = 0;
    for (auto& list : s.deleted) {
      for (uint32_t i : list) {
        vol.clear(s.border[i]);
        vol.set_flags(s.border[i], 0);
        s.own[i] = 0;
      }
      removed += list.size();
      removed_total += list.size();
    }
    s.next_border.clear();
    for (size_t i = 0; i < s.border.size(); ++i) {
      const uint32_t idx = s.border[i];
      const uint8_t f = s.own[i];
      vol.plane_clear_all(idx);
      if (f == 0) continue;  // deleted
      if (f & kK) {
        vol.set_flags(idx, kK);
        s.k_list.push_back(idx);
        ++constrained;
      } else {
        s.next_border.push_back(idx);
      }
    }
    for (auto& list : s.deleted) {
      for (uint32_t i : list)
        for (int d = 0; d < 6; ++d) {
          const uint32_t q = s.border[i] + static_cast<uint32_t>(s.face_off[d]);
          if (vol.get(q) && vol.flags(q) == 0) {
            vol.set_flags(q, kInB);
            s.next_border.push_back(q);
          }
        }
      list.clear();
    }
    s.border.swap(s.next_border);
    ++iterations;
    // Stable when nothing was deleted and K did not grow (a voxel joining K can free a neighbour
    // from a crucial clique it shared with it).
    if ((removed == 0 && constrained == 0) ||
        (options_.max_iterations > 0 && iterations >= options_.max_iterations))
      break;
  }

  vol.store(volume, constraint, s.k_list);
  vol.zero_flags(s.border);
  vol.zero_flags(s.k_list);
  stats.iterations = iterations;
  stats.final_voxels = stats.initial_voxels - removed_total;
  stats.constrained = s.k_list.size();
  return stats;
}

}  // namespace hullpose::thin

namespace hullpose::thin::ck3 {

const RuleTables& host_rule_tables() {
  static const RuleTables tables = [] {
    RuleTables t;
    t.simple_lut = hullpose_simple_lut;
    t.tbar_lut = hullpose_tbar_lut;
    for (int byte = 0; byte < 4; ++byte)
      for (uint32_t x = 0; x < 256; ++x) t.n18_bytes[byte][x] = nb::n18_index(x << (8 * byte));
    for (size_t g = 0; g < 512; ++g) t.ring[g] = detail::kRingTables.bits[g];
    for (int d = 0; d < 6; ++d) t.interior_mask[d] = detail::kInteriorMask[static_cast<size_t>(d)];
    for (int q = 0; q < 4; ++q) t.quadrants[q] = nb::kQuadrants[q];
    for (int o = 0; o < 8; ++o) t.octants[o] = nb::kOctants[o];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 9; ++c)
        t.plane_bit[a][c] = static_cast<uint8_t>(nb::kPlaneCells.bit[a][c]);
    return t;
  }();
  return tables;
}

}  // namespace hullpose::thin::ck3
