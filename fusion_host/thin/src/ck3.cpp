// CK3: one iteration = barrier-separated parallel passes over the border list (notes §2.6, §6):
//   classify (simple / 2D-isthmus / constraint) -> curve rule -> level 2 -> level 1 -> level 0,
//   then a serial pass applies the deletions and grows the border list.
// Each pass reads only what earlier passes wrote and writes only the flags of the voxel it
// evaluates ("voxel-centric", notes §2.7), which makes the marking level-parallel, symmetric and
// independent of thread count and order.
#include <omp.h>

#include <algorithm>
#include <bit>

#include "hullpose/thin/simple_lut.hpp"
#include "hullpose/thin/thinning.hpp"
#include "padded_volume.hpp"
#include "ring_tables.hpp"

namespace hullpose::thin {

namespace {

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
  // only, kPK by the isthmus rule only, and one byte of flags per voxel halves the footprint of
  // the neighbour reads that dominate the passes.
  kPK = kSurf,
};

}  // namespace

const char* to_string(CurveRule rule) {
  switch (rule) {
    case CurveRule::kUltimate: return "ultimate";
    case CurveRule::kCk3: return "ck3";
    case CurveRule::kIsthmus: return "isthmus";
    case CurveRule::kEndVoxel: return "end";
  }
  return "?";
}

struct Ck3Thinner::State {
  detail::PaddedVolume vol;
  std::vector<uint32_t> border, next_border, codes, k_list;
  // Flags of border-list entry i, mirrored from the volume: a pass reads its own voxel's flags
  // in list order (sequential) and only neighbours' from the volume.
  std::vector<uint8_t> own;
  std::vector<std::vector<uint32_t>> deleted;  // per thread: border-list positions
  int face_off[6] = {};
};

Ck3Thinner::Ck3Thinner(const ThinOptions& options) : options_(options), state_(std::make_unique<State>()) {}
Ck3Thinner::~Ck3Thinner() = default;

namespace {

// Members of a clique other than x, given as 27-bit code bits, all "free" (flags & mask == want)?
// Read lazily: most cliques of a border voxel contain an interior voxel, which fails at once.
bool members_free(const detail::PaddedVolume& vol, uint32_t idx, uint32_t members, uint8_t mask, uint8_t want) {
  for (uint32_t m = members & ~nb::kCentreBit; m != 0; m &= m - 1)
    if ((vol.flags(idx + static_cast<uint32_t>(vol.offsets27()[std::countr_zero(m)])) & mask) != want) return false;
  return true;
}
uint32_t plane_members(uint32_t cells, int axis) {
  uint32_t code = 0;
  for (uint32_t c = cells; c != 0; c &= c - 1) code |= 1u << nb::kPlaneCells.bit[axis][std::countr_zero(c)];
  return code;
}

}  // namespace

ThinStats Ck3Thinner::thin(fusion::BitGrid& volume, fusion::BitGrid* constraint) {
  State& s = *state_;
  detail::PaddedVolume& vol = s.vol;
  ThinStats stats;
  stats.initial_voxels = volume.count();
  vol.load(volume, constraint, kK, kInB, s.border, s.k_list);
  for (int d = 0; d < 6; ++d) {
    const auto& [axis, sign] = detail::kDirections[d];
    s.face_off[d] = vol.offset(axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0);
  }
  const int threads = std::max(1, options_.threads);
  s.deleted.resize(static_cast<size_t>(threads));
  const CurveRule rule = options_.rule;
  const bool antipodal = options_.zero_clique == ZeroCliqueTest::kAntipodal;
  const auto& rings = detail::kRingTables;
  int iterations = 0;
  auto set = [&](size_t i, uint32_t idx, uint8_t f) {
    s.own[i] = f;
    vol.set_flags(idx, f);
  };

  while (!s.border.empty()) {
    const std::vector<uint32_t>& border = s.border;
    const size_t n = border.size();
    s.codes.resize(n);
    s.own.resize(n);
    stats.visited += n;
    const bool parallel = threads > 1 && n >= static_cast<size_t>(std::max(0, options_.min_parallel_border));

// The passes, as orphaned worksharing loops: run by every thread of a team, or directly by
    // this thread when the iteration is too small to share (no OpenMP team set up at all).
    auto passes = [&] {
      const int tid = omp_get_thread_num();
      // 1. Codes first, prefetching each one's word of the 8 MiB simple-point LUT, whose misses
      // otherwise dominate the classification. Same static schedule as the next loop, so each
      // thread reads back only codes it wrote (no barrier needed).
#pragma omp for schedule(static) nowait
      for (size_t i = 0; i < n; ++i) {
        const uint32_t code = vol.code(border[i]);
        s.codes[i] = code;
        prefetch_simple(code);
      }
      // Classify: simple, 2D isthmus, constraints of the end-voxel and isthmus rules.
#pragma omp for schedule(static)
      for (size_t i = 0; i < n; ++i) {
        const uint32_t idx = border[i];
        const uint32_t code = s.codes[i];
        uint8_t f = kInB;
        const bool simple = is_simple(code);
        if (rule == CurveRule::kEndVoxel && std::popcount(code & ~nb::kCentreBit) == 1) f |= kK;
        if (rule == CurveRule::kIsthmus && !simple && tbar_class(code) == 1 && nb::t26(code, 3) == 2) f |= kK;
        if (!(f & kK)) {
          if (simple) {
            f |= kS0;
            if (rule == CurveRule::kUltimate || rule == CurveRule::kEndVoxel) f |= kS;
          } else if (tbar_class(code) >= 2) {
            f |= kSurfV;
          }
        }
        set(i, idx, f);
      }

      // 2. Curve rule.
      if (rule == CurveRule::kCk3) {
        // Surface 2-cliques: both voxels candidates, all four axial ring positions occupied.
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
          const uint32_t idx = border[i];
          const uint8_t f = s.own[i];
          if (!(f & kS0)) continue;
          for (int d = 0; d < 6; ++d) {
            const auto& [axis, sign] = detail::kDirections[d];
            if ((vol.flags(idx + s.face_off[d]) & kS0) &&
                (rings.bits[nb::pair_ring(s.codes[i], axis, sign)] & detail::kRingFull4)) {
              set(i, idx, f | kSurf);
              break;
            }
          }
        }
        // Residual voxels (no interior 6-neighbour) with no surface 26-neighbour are curve
        // voxels: not deletable in this iteration (notes §3.3).
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
          const uint32_t idx = border[i];
          const uint8_t f = s.own[i];
          if (!(f & kS0)) continue;
          const uint32_t code = s.codes[i];
          bool residual = true;
          for (int d = 0; d < 6 && residual; ++d) {
            const uint32_t m = detail::kInteriorMask[d];
            if ((code & m) == m && vol.get(idx + 2 * s.face_off[d])) residual = false;
          }
          // Only object neighbours can carry surface marks.
          const bool curve = residual && members_free(vol, idx, code, kSurf | kSurfV, 0);
          if (!curve) set(i, idx, f | kS);
        }
      } else if (rule == CurveRule::kIsthmus) {
        // 2-clique isthmus (T4̄ != 0, T8 = 2), recording crucial 2-cliques for the 1-clique step.
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
          const uint32_t idx = border[i];
          uint8_t f = s.own[i];
          if (!(f & kS0)) continue;
          for (int d = 0; d < 6; ++d) {
            const auto& [axis, sign] = detail::kDirections[d];
            if (!(vol.flags(idx + s.face_off[d]) & kS0)) continue;
            const uint8_t r = rings.bits[nb::pair_ring(s.codes[i], axis, sign)];
            if (r & detail::kRingCrucial) f |= kZ2;
            if (r & detail::kRingIsthmus) f |= kPK;
          }
          set(i, idx, f);
        }
        // 1-clique isthmus: candidates only, none marked at the 2-clique step, both caps non-empty.
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
          const uint32_t idx = border[i];
          const uint8_t f = s.own[i];
          if ((f & (kS0 | kZ2)) != kS0) continue;
          const uint32_t code = s.codes[i];
          bool isthmus = false;
          for (int axis = 0; axis < 3 && !isthmus; ++axis) {
            const uint32_t p0 = nb::plane9(code, axis, 0), lo = nb::plane9(code, axis, -1), hi = nb::plane9(code, axis, 1);
            for (const nb::Quadrant& q : nb::kQuadrants)
              if (nb::quadrant_has_diagonal(p0, q) && (lo & q.cells) && (hi & q.cells) &&
                  members_free(vol, idx, plane_members(p0 & q.cells, axis), kS0 | kZ2, kS0)) {
                isthmus = true;
                break;
              }
          }
          if (isthmus) set(i, idx, f | kPK);
        }
        // Isthmuses join K for good; the other candidates go on, marks cleared.
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
          const uint32_t idx = border[i];
          const uint8_t f = s.own[i];
          if (f & kPK)
            set(i, idx, kInB | kK);
          else if (f & kS0)
            set(i, idx, static_cast<uint8_t>((f & ~kZ2) | kS));
        }
      }

      // 3. Level 2: crucial 2-cliques of two candidates.
#pragma omp for schedule(static)
      for (size_t i = 0; i < n; ++i) {
        const uint32_t idx = border[i];
        const uint8_t f = s.own[i];
        if (!(f & kS)) continue;
        for (int d = 0; d < 6; ++d) {
          const auto& [axis, sign] = detail::kDirections[d];
          if ((vol.flags(idx + s.face_off[d]) & kS) &&
              (rings.bits[nb::pair_ring(s.codes[i], axis, sign)] & detail::kRingCrucial)) {
            set(i, idx, f | kZ2);
            break;
          }
        }
      }
      // 4. Level 1: crucial 1-cliques of unmarked candidates (level-2 marks only).
#pragma omp for schedule(static)
      for (size_t i = 0; i < n; ++i) {
        const uint32_t idx = border[i];
        const uint8_t f = s.own[i];
        if ((f & (kS | kZ2)) != kS) continue;
        const uint32_t code = s.codes[i];
        bool marked = false;
        for (int axis = 0; axis < 3 && !marked; ++axis) {
          const uint32_t p0 = nb::plane9(code, axis, 0), lo = nb::plane9(code, axis, -1), hi = nb::plane9(code, axis, 1);
          for (const nb::Quadrant& q : nb::kQuadrants)
            if (nb::quadrant_has_diagonal(p0, q) && nb::edge_crucial(lo, hi, q) &&
                members_free(vol, idx, plane_members(p0 & q.cells, axis), kS | kZ2, kS)) {
              marked = true;
              break;
            }
        }
        if (marked) set(i, idx, f | kZ1);
      }
      // 5. Level 0: essential 0-cliques of unmarked candidates; what stays unmarked is deleted.
      std::vector<uint32_t>& deleted = s.deleted[static_cast<size_t>(tid)];
#pragma omp for schedule(static)
      for (size_t i = 0; i < n; ++i) {
        const uint32_t idx = border[i];
        const uint8_t f = s.own[i];
        if ((f & (kS | kZ2 | kZ1)) != kS) continue;
        const uint32_t code = s.codes[i];
        bool marked = false;
        for (const nb::Octant& o : nb::kOctants) {
          const uint32_t block = code & o.cells;
          if ((antipodal ? nb::block_antipodal(block, o) : nb::block_spans3(block, o)) &&
              members_free(vol, idx, block, kS | kZ2 | kZ1, kS)) {
            marked = true;
            break;
          }
        }
        if (!marked) deleted.push_back(static_cast<uint32_t>(i));
      }
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
        set(i, s.border[i], 0);
      }
      removed += list.size();
    }
    s.next_border.clear();
    for (size_t i = 0; i < s.border.size(); ++i) {
      const uint32_t idx = s.border[i];
      const uint8_t f = s.own[i];
      if (f == 0) continue;  // deleted
      if (f & kK) {
        set(i, idx, kK);
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
    if ((removed == 0 && constrained == 0) || (options_.max_iterations > 0 && iterations >= options_.max_iterations))
      break;
  }

  vol.store(volume, constraint, s.k_list);
  vol.zero_flags(s.border);
  vol.zero_flags(s.k_list);
  stats.iterations = iterations;
  stats.final_voxels = volume.count();
  stats.constrained = s.k_list.size();
  return stats;
}

}  // namespace hullpose::thin
