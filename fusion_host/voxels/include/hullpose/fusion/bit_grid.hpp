#pragma once
// A binary voxel volume, one bit per voxel: rows along x packed into 64-bit words, rows ordered
// y fastest then z (the voxel order of common/voxel_grid.hpp). The currency between carving,
// clean-up and thinning: 128³ is 256 KiB, so whole-volume word operations stay in cache.
#include <Eigen/Core>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hullpose::fusion {

class BitGrid {
 public:
  BitGrid() = default;
  explicit BitGrid(const Eigen::Vector3i& dims) { reset(dims); }

  // Resizes to `dims` and clears; reuses the allocation when the size does not grow.
  void reset(const Eigen::Vector3i& dims) {
    dims_ = dims;
    words_per_row_ = (dims.x() + 63) / 64;
    words_.assign(static_cast<size_t>(words_per_row_) * dims.y() * dims.z(), 0);
  }
  void clear() { std::fill(words_.begin(), words_.end(), 0); }

  const Eigen::Vector3i& dims() const { return dims_; }
  int words_per_row() const { return words_per_row_; }
  size_t row_index(int y, int z) const {
    return (static_cast<size_t>(z) * dims_.y() + y) * words_per_row_;
  }
  uint64_t* row(int y, int z) { return words_.data() + row_index(y, z); }
  const uint64_t* row(int y, int z) const { return words_.data() + row_index(y, z); }
  std::vector<uint64_t>& words() { return words_; }
  const std::vector<uint64_t>& words() const { return words_; }

  bool contains(int x, int y, int z) const {
    return x >= 0 && y >= 0 && z >= 0 && x < dims_.x() && y < dims_.y() && z < dims_.z();
  }
  bool get(int x, int y, int z) const { return (row(y, z)[x >> 6] >> (x & 63) & 1u) != 0; }
  // Out-of-range reads are background.
  bool get_or_zero(int x, int y, int z) const { return contains(x, y, z) && get(x, y, z); }
  void set(int x, int y, int z, bool v = true) {
    uint64_t& w = row(y, z)[x >> 6];
    const uint64_t m = uint64_t{1} << (x & 63);
    w = v ? (w | m) : (w & ~m);
  }
  size_t count() const {
    size_t n = 0;
    for (uint64_t w : words_) n += static_cast<size_t>(std::popcount(w));
    return n;
  }
  // Calls f(x, y, z) for every set voxel in x-fastest order.
  template <typename F>
  void for_each(F&& f) const {
    for (int z = 0; z < dims_.z(); ++z)
      for (int y = 0; y < dims_.y(); ++y) {
        const uint64_t* r = row(y, z);
        for (int w = 0; w < words_per_row_; ++w)
          for (uint64_t bits = r[w]; bits != 0; bits &= bits - 1)
            f(w * 64 + std::countr_zero(bits), y, z);
      }
  }
  bool operator==(const BitGrid& o) const { return dims_ == o.dims_ && words_ == o.words_; }

 private:
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  int words_per_row_ = 0;
  std::vector<uint64_t> words_;
};

}  // namespace hullpose::fusion
