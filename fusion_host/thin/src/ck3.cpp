// CK3: one iteration = barrier-separated parallel passes over the border list (notes §2.6, §6):
//   classify (simple / 2D-isthmus / constraint) -> curve rule -> level 2 -> level 1 -> level 0,
//   then a serial pass applies the deletions and grows the border list.
// Each pass reads only what earlier passes wrote and writes only the flags of the voxel it
// evaluates ("voxel-centric", notes §2.7), which makes the marking level-parallel, symmetric and
// independent of thread count and order.
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

// PaddedVolume as the shared rules read it (ck3_rules.hpp).
struct VolumeView {
  const detail::PaddedVolume& vol;
  const int* faces;
  uint8_t flags(uint32_t idx) const { return vol.flags(idx); }
  bool get(uint32_t idx) const { return vol.get(idx); }
  int off27(int bit) const { return vol.offsets27()[bit]; }
  int face(int d) const { return faces[d]; }
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
  const RuleTables& tables = host_rule_tables();
  const VolumeView view{vol, s.face_off};
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
    // this thread when the iteration is too small to share (no OpenMP team set up at all). The
    // per-voxel decisions are ck3_rules.hpp's, shared with the CUDA backend.
    auto passes = [&] {
      const int tid = omp_get_thread_num();
      // Each pass: the voxel's new flags from its own, its code and its neighbours' flags.
      auto pass = [&](auto&& rule_fn) {
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; ++i) {
          const uint8_t f = s.own[i];
          const uint8_t nf = rule_fn(border[i], s.codes[i], f);
          if (nf != f) set(i, border[i], nf);
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
      for (size_t i = 0; i < n; ++i) set(i, border[i], classify(tables, rule, s.codes[i]));

      // 2. Curve rule.
      if (rule == CurveRule::kCk3) {
        pass([&](uint32_t idx, uint32_t code, uint8_t f) { return ck3_surface(view, tables, idx, code, f); });
        pass([&](uint32_t idx, uint32_t code, uint8_t f) { return ck3_candidate(view, tables, idx, code, f); });
      } else if (rule == CurveRule::kIsthmus) {
        pass([&](uint32_t idx, uint32_t code, uint8_t f) { return isthmus_pairs(view, tables, idx, code, f); });
        pass([&](uint32_t idx, uint32_t code, uint8_t f) { return isthmus_edges(view, tables, idx, code, f); });
        pass([&](uint32_t, uint32_t, uint8_t f) { return isthmus_settle(f); });
      }
      // 3.-4. Levels 2 and 1.
      pass([&](uint32_t idx, uint32_t code, uint8_t f) { return level2(view, tables, idx, code, f); });
      pass([&](uint32_t idx, uint32_t code, uint8_t f) { return level1(view, tables, idx, code, f); });
      // 5. Level 0: what stays unmarked is deleted.
      std::vector<uint32_t>& deleted = s.deleted[static_cast<size_t>(tid)];
#pragma omp for schedule(static)
      for (size_t i = 0; i < n; ++i)
        if (level0_deletes(view, tables, border[i], s.codes[i], s.own[i], options_.zero_clique))
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
        set(i, s.border[i], 0);
      }
      removed += list.size();
      removed_total += list.size();
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
      for (int c = 0; c < 9; ++c) t.plane_bit[a][c] = static_cast<uint8_t>(nb::kPlaneCells.bit[a][c]);
    return t;
  }();
  return tables;
}

}  // namespace hullpose::thin::ck3
