// D6I1D (Raynal & Couprie, DGCI 2011) after notes §4: six directional sub-iterations per
// iteration, 1D isthmuses accumulated into K at the end of each iteration. Raynal's 64 MiB
// deletability table is not published; deletability here is our own construction (notes §4.4):
// in direction α a simple α-border voxel is deleted unless it is the designated keeper of a
// crucial clique that contains it. The keeper is the member furthest from the α side
// (ties broken by z, y, x), a choice every member of the clique computes identically from its
// own 3x3x3 neighbourhood, so each crucial clique keeps a voxel and every sub-iteration preserves
// topology (critical-kernel theorem, notes §2.1).
#include <algorithm>

#include "hullpose/thin/simple_lut.hpp"
#include "hullpose/thin/thinning.hpp"
#include "padded_volume.hpp"
#include "ring_tables.hpp"

namespace hullpose::thin {

namespace {

enum : uint8_t { kK = 1, kInB = 2 };

// Neighbourhood offsets r ordered before the centre for direction d: (sign * r_axis, r_z, r_y, r_x)
// lexicographically smaller than zero.
constexpr uint32_t before_mask(int d) {
  const auto [axis, sign] = detail::kDirections[d];
  uint32_t m = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int r[3] = {dx, dy, dz};
        const int key[4] = {sign * r[axis], dz, dy, dx};
        bool less = false;
        for (int k : key)
          if (k != 0) {
            less = k < 0;
            break;
          }
        if (less) m |= 1u << nb::bit(dx, dy, dz);
      }
  return m;
}

struct KeeperMasks {
  uint32_t before[6] = {};
  uint32_t before_plane[6][3] = {};
  constexpr KeeperMasks() {
    for (int d = 0; d < 6; ++d) {
      before[d] = before_mask(d);
      for (int axis = 0; axis < 3; ++axis) before_plane[d][axis] = nb::plane9(before[d], axis, 0);
    }
  }
};
constexpr KeeperMasks kKeeper;

bool isthmus_1d(uint32_t code) {
  return !is_simple(code) && tbar_class(code) == 1 && nb::t26(code, 3) == 2;
}

// Deletable in direction d (notes §4.4); `code` is the voxel's neighbourhood, the voxel not in K.
bool deletable(uint32_t code, int d) {
  const auto [axis_d, sign_d] = detail::kDirections[d];
  if (code &
      (1u << nb::bit(axis_d == 0 ? sign_d : 0, axis_d == 1 ? sign_d : 0, axis_d == 2 ? sign_d : 0)))
    return false;
  if (!is_simple(code)) return false;
  const uint32_t before = kKeeper.before[d];
  for (int e = 0; e < 6; ++e) {  // 2-cliques {x, x + e}
    const auto [axis, sign] = detail::kDirections[e];
    const uint32_t eb =
        1u << nb::bit(axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0);
    if (!(code & eb) || (eb & before)) continue;  // not a clique, or x is not its keeper
    if (detail::kRingTables.bits[nb::pair_ring(code, axis, sign)] & ck3::kRingCrucial) return false;
  }
  for (int axis = 0; axis < 3; ++axis) {  // 1-cliques around the 12 edges of x
    const uint32_t p0 = nb::plane9(code, axis, 0), lo = nb::plane9(code, axis, -1),
                   hi = nb::plane9(code, axis, 1);
    for (const nb::Quadrant& q : nb::kQuadrants)
      if ((p0 & q.cells & kKeeper.before_plane[d][axis]) == 0 && nb::quadrant_has_diagonal(p0, q) &&
          nb::edge_crucial(lo, hi, q))
        return false;
  }
  for (const nb::Octant& o : nb::kOctants) {  // 0-cliques
    const uint32_t block = code & o.cells;
    if ((block & before) == 0 && nb::block_spans3(block, o)) return false;
  }
  return true;
}

}  // namespace

struct D6i1dThinner::State {
  detail::PaddedVolume vol;
  std::vector<uint32_t> border, pending, k_list, deleted;
  int face_off[6] = {};
};

D6i1dThinner::D6i1dThinner(const D6i1dOptions& options)
    : options_(options), state_(std::make_unique<State>()) {}
D6i1dThinner::~D6i1dThinner() = default;

ThinStats D6i1dThinner::thin(fusion::BitGrid& volume, fusion::BitGrid* constraint) {
  State& s = *state_;
  detail::PaddedVolume& vol = s.vol;
  ThinStats stats;
  stats.initial_voxels = volume.count();
  vol.load(volume, constraint, kK, kInB, s.border, s.k_list);
  for (int d = 0; d < 6; ++d) {
    const auto& [axis, sign] = detail::kDirections[d];
    s.face_off[d] = vol.offset(axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0);
  }
  // Isthmuses of the border join K; the rest is the border list.
  auto move_isthmuses_to_k = [&] {
    size_t keep = 0;
    for (uint32_t idx : s.border) {
      if (isthmus_1d(vol.code(idx))) {
        vol.set_flags(idx, kK);
        s.k_list.push_back(idx);
      } else {
        s.border[keep++] = idx;
      }
    }
    s.border.resize(keep);
  };
  move_isthmuses_to_k();
  s.pending.clear();
  for (;;) {
    size_t removed = 0;
    for (int d = 0; d < 6; ++d) {
      s.deleted.clear();
      for (uint32_t idx : s.border)
        if (deletable(vol.code(idx), d)) s.deleted.push_back(idx);
      stats.visited += s.border.size();
      for (uint32_t idx : s.deleted) {
        vol.clear(idx);
        vol.set_flags(idx, 0);
      }
      for (uint32_t idx : s.deleted)
        for (int e = 0; e < 6; ++e) {
          const uint32_t q = idx + static_cast<uint32_t>(s.face_off[e]);
          if (vol.get(q) && vol.flags(q) == 0) {
            vol.set_flags(q, kInB);
            s.pending.push_back(q);
          }
        }
      s.border.erase(std::remove_if(s.border.begin(), s.border.end(),
                                    [&](uint32_t idx) { return vol.flags(idx) == 0; }),
                     s.border.end());
      removed += s.deleted.size();
    }
    s.border.insert(s.border.end(), s.pending.begin(), s.pending.end());
    s.pending.clear();
    move_isthmuses_to_k();
    ++stats.iterations;
    if (removed == 0 ||
        (options_.max_iterations > 0 && stats.iterations >= options_.max_iterations))
      break;
  }
  vol.store(volume, constraint, s.k_list);
  vol.zero_flags(s.border);
  vol.zero_flags(s.k_list);
  stats.final_voxels = volume.count();
  stats.constrained = s.k_list.size();
  return stats;
}

}  // namespace hullpose::thin
