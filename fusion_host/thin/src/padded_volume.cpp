#include "padded_volume.hpp"

#include <bit>

#include "hullpose/common/check.hpp"

namespace hullpose::thin::detail {

namespace {

// 64 bits of a bit row starting at bit `b` (may be negative or run past the end: zeros there).
uint64_t bits_at(const uint64_t* row, int64_t words, int64_t b) {
  const int64_t w = b >> 6;  // floor, also for negative b
  const int s = static_cast<int>(b & 63);
  const uint64_t lo = w >= 0 && w < words ? row[w] : 0;
  if (s == 0) return lo;
  const uint64_t hi = w + 1 >= 0 && w + 1 < words ? row[w + 1] : 0;
  return lo >> s | hi << (64 - s);
}

}  // namespace

void PaddedVolume::load(const fusion::BitGrid& grid, const fusion::BitGrid* constraint,
                        uint8_t k_flag, uint8_t inb_flag, std::vector<uint32_t>& border,
                        std::vector<uint32_t>& k_list) {
  const Eigen::Vector3i dims = grid.dims();
  HULLPOSE_THROW_UNLESS((dims.array() > 0).all(),
                        "thinning: empty volume dims " << dims.transpose());
  if (constraint && constraint->dims().prod() == 0) constraint = nullptr;  // output only
  HULLPOSE_THROW_UNLESS(!constraint || constraint->dims() == dims,
                        "thinning: constraint dims " << constraint->dims().transpose()
                                                     << " differ from volume dims "
                                                     << dims.transpose());
  dims_ = dims;
  // Work on the object's bounding box only: a person fills a small part of the capture volume,
  // and every per-frame cost here (copy, border scan, flag-array footprint) scales with it.
  const int gw = grid.words_per_row();
  column_or_.assign(static_cast<size_t>(gw), 0);
  voxels_ = 0;
  Eigen::Vector3i lo(0, dims.y(), dims.z()), hi(0, -1, -1);  // inclusive y, z range
  for (int z = 0; z < dims.z(); ++z)
    for (int y = 0; y < dims.y(); ++y) {
      const uint64_t* src = grid.row(y, z);
      uint64_t any = 0;
      for (int w = 0; w < gw; ++w) {
        column_or_[static_cast<size_t>(w)] |= src[w];
        any |= src[w];
        voxels_ += static_cast<size_t>(std::popcount(src[w]));
      }
      if (any == 0) continue;
      lo.y() = std::min(lo.y(), y);
      hi.y() = std::max(hi.y(), y);
      lo.z() = std::min(lo.z(), z);
      hi.z() = std::max(hi.z(), z);
    }
  if (hi.z() < 0) {  // empty object: a one-voxel box
    lo.setZero();
    hi.setZero();
  } else {
    int w0 = 0, w1 = gw - 1;
    while (column_or_[static_cast<size_t>(w0)] == 0) ++w0;
    while (column_or_[static_cast<size_t>(w1)] == 0) --w1;
    lo.x() = w0 * 64 + std::countr_zero(column_or_[static_cast<size_t>(w0)]);
    hi.x() = w1 * 64 + 63 - std::countl_zero(column_or_[static_cast<size_t>(w1)]);
  }
  lo_ = lo;
  const Eigen::Vector3i box = hi - lo + Eigen::Vector3i::Ones();
  px_ = box.x() + 2 * kPad;
  py_ = box.y() + 2 * kPad;
  pz_ = box.z() + 2 * kPad;
  shift_ = std::bit_width(static_cast<unsigned>(px_ - 1));
  mask_ = (1u << shift_) - 1;
  const uint64_t padded = (static_cast<uint64_t>(py_) * pz_) << shift_;
  HULLPOSE_THROW_UNLESS(padded < (uint64_t{1} << 31),
                        "thinning: volume " << dims.transpose() << " too large");
  words_ = static_cast<size_t>((px_ + 63) / 64 + 1);
  rows_.assign(static_cast<size_t>(py_) * pz_ * words_, 0);
  for (auto& p : planes_) p.assign(rows_.size(), 0);
  if (flags_.size() < padded) flags_.resize(padded, 0);  // invariant: all zero between frames
  for (int b = 0; b < 27; ++b) off27_[b] = offset(b % 3 - 1, b / 3 % 3 - 1, b / 9 - 1);

  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y) {
      const uint64_t* src = grid.row(y, z);
      uint64_t* dst = rows_.data() +
                      (static_cast<size_t>(z - lo.z() + kPad) * py_ + y - lo.y() + kPad) * words_;
      // Padded bit p holds grid bit p - kPad + lo.x; bits outside the box are zero in the grid.
      for (size_t w = 0; w + 1 < words_; ++w)
        dst[w] = bits_at(src, gw, static_cast<int64_t>(w) * 64 - kPad + lo.x());
    }

  border.clear();
  k_list.clear();
  if (constraint)
    constraint->for_each([&](int x, int y, int z) {
      const Eigen::Vector3i p = Eigen::Vector3i(x, y, z) - lo_;
      if ((p.array() < 0).any() || (p.array() >= box.array()).any()) return;  // not an object voxel
      const uint32_t idx = index(p.x() + kPad, p.y() + kPad, p.z() + kPad);
      if (!get(idx)) return;
      set_flags(idx, k_flag);
      k_list.push_back(idx);
    });
  // 6-border voxels, a word at a time: X & ~(all six face neighbours set).
  const size_t nw = words_ - 1;
  for (int z = kPad; z < pz_ - kPad; ++z)
    for (int y = kPad; y < py_ - kPad; ++y) {
      const uint64_t* r = rows_.data() + (static_cast<size_t>(z) * py_ + y) * words_;
      for (size_t w = 0; w < nw; ++w) {
        if (r[w] == 0) continue;
        const uint64_t left = r[w] << 1 | (w > 0 ? r[w - 1] >> 63 : 0);
        const uint64_t right = r[w] >> 1 | r[w + 1] << 63;
        const uint64_t inner = left & right & r[w - words_] & r[w + words_] &
                               r[w - words_ * static_cast<size_t>(py_)] &
                               r[w + words_ * static_cast<size_t>(py_)];
        for (uint64_t bits = r[w] & ~inner; bits != 0; bits &= bits - 1) {
          const uint32_t idx = index(static_cast<int>(w * 64) + std::countr_zero(bits), y, z);
          if (flags(idx) & k_flag) continue;
          set_flags(idx, inb_flag);
          border.push_back(idx);
        }
      }
    }
}

void PaddedVolume::store(fusion::BitGrid& grid, fusion::BitGrid* constraint,
                         const std::vector<uint32_t>& k_list) const {
  HULLPOSE_ASSERT(grid.dims() == dims_);
  // Thinning only deletes, so the grid outside the box is still empty: rewrite the box's rows.
  const int gw = grid.words_per_row();
  const int tail = dims_.x() % 64;
  const uint64_t last_mask = tail == 0 ? ~uint64_t{0} : (uint64_t{1} << tail) - 1;
  for (int z = 0; z < pz_ - 2 * kPad; ++z)
    for (int y = 0; y < py_ - 2 * kPad; ++y) {
      uint64_t* dst = grid.row(y + lo_.y(), z + lo_.z());
      const uint64_t* src =
          rows_.data() + (static_cast<size_t>(z + kPad) * py_ + y + kPad) * words_;
      for (int w = 0; w < gw; ++w)
        dst[w] = bits_at(src, static_cast<int64_t>(words_),
                         static_cast<int64_t>(w) * 64 + kPad - lo_.x());
      dst[gw - 1] &= last_mask;
    }
  if (constraint) {
    constraint->reset(dims_);
    for (uint32_t idx : k_list) {
      const int x = static_cast<int>(idx & mask_);
      const int y = static_cast<int>((idx >> shift_) % static_cast<uint32_t>(py_));
      const int z = static_cast<int>((idx >> shift_) / static_cast<uint32_t>(py_));
      constraint->set(x - kPad + lo_.x(), y - kPad + lo_.y(), z - kPad + lo_.z());
    }
  }
}

}  // namespace hullpose::thin::detail
