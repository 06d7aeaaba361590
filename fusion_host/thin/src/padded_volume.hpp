#pragma once
// The thinners' working volume: the object's bounding box as bit rows with 2 background voxels
// of padding on every side (clique tests read up to 2 voxels away, notes §0), a per-voxel flag
// word, and the border list. Internal to hullpose_thin.
#include <atomic>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/thin/neighbourhood.hpp"

namespace hullpose::thin::detail {

inline constexpr int kPad = 2;

class PaddedVolume {
 public:
  // Copies `grid` in (and `constraint`'s object voxels into flag `k_flag`); fills `border` with
  // the 6-border voxels not in K and sets `inb_flag` on them. Flags must be all zero on entry
  // (zero_flags() restores that), so a frame never pays for clearing the whole flag volume.
  void load(const fusion::BitGrid& grid, const fusion::BitGrid* constraint, uint8_t k_flag,
            uint8_t inb_flag, std::vector<uint32_t>& border, std::vector<uint32_t>& k_list);
  // Object voxels counted by the last load().
  size_t voxels() const { return voxels_; }
  // Writes the object back into `grid` (same dims as loaded) and K into `constraint`.
  void store(fusion::BitGrid& grid, fusion::BitGrid* constraint,
             const std::vector<uint32_t>& k_list) const;

  // Linear voxel index: (row << shift) | x with row = z * py + y, the row stride a power of two
  // so that no per-voxel access divides.
  uint32_t index(int x, int y, int z) const {
    return (static_cast<uint32_t>(z * py_ + y) << shift_) | static_cast<uint32_t>(x);
  }
  // Linear index offset of a neighbour.
  int offset(int dx, int dy, int dz) const { return dx + (dy + py_ * dz) * (1 << shift_); }
  const int* offsets27() const { return off27_; }

  bool get(uint32_t idx) const {
    const uint32_t row = idx >> shift_, x = idx & mask_;
    return (rows_[row * words_ + (x >> 6)] >> (x & 63) & 1u) != 0;
  }
  void clear(uint32_t idx) {
    const uint32_t row = idx >> shift_, x = idx & mask_;
    rows_[row * words_ + (x >> 6)] &= ~(uint64_t{1} << (x & 63));
  }

  // The 27-bit neighbourhood code of voxel idx (notes §0), from 9 unaligned row reads.
  uint32_t code(uint32_t idx) const { return gather(rows_.data(), idx); }

  // Bit planes with the object's layout, one per per-voxel flag the thinner's passes read from
  // neighbours: a pass gathers a neighbour flag as a 27-bit code with the 9 row reads of code()
  // instead of 26 byte reads and branches. Zero on load(); the thinner clears what it sets.
  static constexpr int kPlanes = 5;
  uint32_t plane_code(int plane, uint32_t idx) const { return gather(planes_[plane].data(), idx); }
  // Sets the bit; `shared`: other threads set bits of the same words in this pass.
  void plane_set(int plane, uint32_t idx, bool shared) {
    uint64_t& w = planes_[plane][word_of(idx)];
    const uint64_t m = uint64_t{1} << (idx & mask_ & 63);
    if (shared)
      std::atomic_ref<uint64_t>(w).fetch_or(m, std::memory_order_relaxed);
    else
      w |= m;
  }
  void plane_clear_all(uint32_t idx) {
    const size_t w = word_of(idx);
    const uint64_t m = ~(uint64_t{1} << (idx & mask_ & 63));
    for (auto& p : planes_) p[w] &= m;
  }

 private:
  size_t word_of(uint32_t idx) const { return (idx >> shift_) * words_ + ((idx & mask_) >> 6); }
  uint32_t gather(const uint64_t* rows, uint32_t idx) const {
    const uint32_t row = idx >> shift_, x = (idx & mask_) - 1;
    const auto* base = reinterpret_cast<const unsigned char*>(rows);
    uint32_t c = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        const size_t r = static_cast<size_t>(static_cast<int>(row) + dy + dz * py_);
        uint64_t w;
        std::memcpy(&w, base + (r * words_) * 8 + (x >> 3), 8);
        c |= static_cast<uint32_t>(w >> (x & 7) & 7u) << ((dz + 1) * 9 + (dy + 1) * 3);
      }
    return c;
  }

 public:
  // Per-voxel flags; each pass writes only the flags of the voxel it evaluates while other
  // threads read neighbours', hence relaxed atomics (plain moves on x86).
  uint8_t flags(uint32_t idx) const {
    return std::atomic_ref<uint8_t>(const_cast<uint8_t&>(flags_[idx]))
        .load(std::memory_order_relaxed);
  }
  void set_flags(uint32_t idx, uint8_t f) {
    std::atomic_ref<uint8_t>(flags_[idx]).store(f, std::memory_order_relaxed);
  }
  // Back to the all-zero flag invariant for the listed voxels (call at the end of a frame with
  // every voxel whose flags were set).
  void zero_flags(const std::vector<uint32_t>& list) {
    for (uint32_t idx : list) flags_[idx] = 0;
  }

 private:
  int px_ = 0, py_ = 0, pz_ = 0;
  int shift_ = 0;
  uint32_t mask_ = 0;
  size_t words_ = 0;  // per padded row, including one spare word for the unaligned reads
  int off27_[27] = {};
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();  // the grid's
  Eigen::Vector3i lo_ =
      Eigen::Vector3i::Zero();  // grid coordinates of the object's bounding box corner
  std::vector<uint64_t> column_or_;
  size_t voxels_ = 0;
  std::vector<uint64_t> rows_;
  std::vector<uint64_t> planes_[kPlanes];
  std::vector<uint8_t> flags_;
};

}  // namespace hullpose::thin::detail
