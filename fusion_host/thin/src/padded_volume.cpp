#include "padded_volume.hpp"

#include <bit>

#include "hullpose/common/check.hpp"

namespace hullpose::thin::detail {

void PaddedVolume::load(const fusion::BitGrid& grid, const fusion::BitGrid* constraint, uint16_t k_flag,
                        uint16_t inb_flag, std::vector<uint32_t>& border, std::vector<uint32_t>& k_list) {
  const Eigen::Vector3i dims = grid.dims();
  HULLPOSE_THROW_UNLESS((dims.array() > 0).all(), "thinning: empty volume dims " << dims.transpose());
  if (constraint && constraint->dims().prod() == 0) constraint = nullptr;  // output only
  HULLPOSE_THROW_UNLESS(!constraint || constraint->dims() == dims,
                        "thinning: constraint dims " << constraint->dims().transpose() << " differ from volume dims "
                                                     << dims.transpose());
  dims_ = dims;
  px_ = dims.x() + 2 * kPad;
  py_ = dims.y() + 2 * kPad;
  pz_ = dims.z() + 2 * kPad;
  shift_ = std::bit_width(static_cast<unsigned>(px_ - 1));
  mask_ = (1u << shift_) - 1;
  const uint64_t padded = (static_cast<uint64_t>(py_) * pz_) << shift_;
  HULLPOSE_THROW_UNLESS(padded < (uint64_t{1} << 31), "thinning: volume " << dims.transpose() << " too large");
  words_ = static_cast<size_t>((px_ + 63) / 64 + 1);
  rows_.assign(static_cast<size_t>(py_) * pz_ * words_, 0);
  if (flags_.size() < padded) flags_.resize(padded, 0);  // invariant: all zero between frames
  for (int b = 0; b < 27; ++b) off27_[b] = offset(b % 3 - 1, b / 3 % 3 - 1, b / 9 - 1);

  const int gw = grid.words_per_row();
  for (int z = 0; z < dims.z(); ++z)
    for (int y = 0; y < dims.y(); ++y) {
      const uint64_t* src = grid.row(y, z);
      uint64_t* dst = rows_.data() + (static_cast<size_t>(z + kPad) * py_ + y + kPad) * words_;
      for (int w = 0; w < gw; ++w) {
        dst[w] |= src[w] << kPad;
        dst[w + 1] |= src[w] >> (64 - kPad);
      }
    }

  border.clear();
  k_list.clear();
  if (constraint)
    constraint->for_each([&](int x, int y, int z) {
      const uint32_t idx = index(x + kPad, y + kPad, z + kPad);
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
                               r[w - words_ * static_cast<size_t>(py_)] & r[w + words_ * static_cast<size_t>(py_)];
        for (uint64_t bits = r[w] & ~inner; bits != 0; bits &= bits - 1) {
          const uint32_t idx = index(static_cast<int>(w * 64) + std::countr_zero(bits), y, z);
          if (flags(idx) & k_flag) continue;
          set_flags(idx, inb_flag);
          border.push_back(idx);
        }
      }
    }
}

void PaddedVolume::store(fusion::BitGrid& grid, fusion::BitGrid* constraint, const std::vector<uint32_t>& k_list) const {
  HULLPOSE_ASSERT(grid.dims() == dims_);
  const int gw = grid.words_per_row();
  const int tail = dims_.x() % 64;
  const uint64_t last_mask = tail == 0 ? ~uint64_t{0} : (uint64_t{1} << tail) - 1;
  for (int z = 0; z < dims_.z(); ++z)
    for (int y = 0; y < dims_.y(); ++y) {
      uint64_t* dst = grid.row(y, z);
      const uint64_t* src = rows_.data() + (static_cast<size_t>(z + kPad) * py_ + y + kPad) * words_;
      for (int w = 0; w < gw; ++w) dst[w] = src[w] >> kPad | src[w + 1] << (64 - kPad);
      dst[gw - 1] &= last_mask;
    }
  if (constraint) {
    constraint->reset(dims_);
    for (uint32_t idx : k_list) {
      const int x = static_cast<int>(idx & mask_);
      const int y = static_cast<int>((idx >> shift_) % static_cast<uint32_t>(py_));
      const int z = static_cast<int>((idx >> shift_) / static_cast<uint32_t>(py_));
      constraint->set(x - kPad, y - kPad, z - kPad);
    }
  }
}

}  // namespace hullpose::thin::detail
