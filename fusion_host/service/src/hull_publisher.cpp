#include "hullpose/fusion_host/hull_publisher.hpp"

#include <algorithm>
#include <bit>
#include <climits>

#include "hullpose/common/check.hpp"
#include "hullpose/msg/wire.hpp"

namespace hullpose::fusion {

void coarsen_hull(const BitGrid& fine, const VoxelGridSpec& grid, int max_dim, msg::CoarseHull& out,
                  std::vector<uint64_t>& merged) {
  const Eigen::Vector3i& d = fine.dims();
  const int f = std::max(1, (d.maxCoeff() + max_dim - 1) / max_dim);
  const int nx = (d.x() + f - 1) / f, ny = (d.y() + f - 1) / f, nz = (d.z() + f - 1) / f;
  out.dims = {nx, ny, nz};
  out.origin_mm = {static_cast<float>(grid.origin_mm.x()), static_cast<float>(grid.origin_mm.y()),
                   static_cast<float>(grid.origin_mm.z())};
  out.voxel_mm = static_cast<float>(grid.voxel_mm * f);
  out.carved_voxel_mm = static_cast<float>(grid.voxel_mm);
  out.occupancy.create(ny * nz, nx, CV_8UC1);
  out.occupancy.setTo(0);
  out.num_occupied = 0;
  const int words = fine.words_per_row();
  // OR the f x f fine rows of each coarse row word-wise, then mark x / f of every set bit: the
  // cost follows the occupied voxels, not the volume.
  merged.resize(static_cast<size_t>(words));
  for (int cz = 0; cz < nz; ++cz)
    for (int cy = 0; cy < ny; ++cy) {
      std::fill(merged.begin(), merged.end(), 0);
      for (int z = cz * f; z < std::min(d.z(), (cz + 1) * f); ++z)
        for (int y = cy * f; y < std::min(d.y(), (cy + 1) * f); ++y) {
          const uint64_t* r = fine.row(y, z);
          for (int w = 0; w < words; ++w) merged[static_cast<size_t>(w)] |= r[w];
        }
      uint8_t* row = out.occupancy.ptr<uint8_t>(cy + ny * cz);
      for (int w = 0; w < words; ++w)
        for (uint64_t bits = merged[static_cast<size_t>(w)]; bits != 0; bits &= bits - 1) {
          uint8_t& v = row[(w * 64 + std::countr_zero(bits)) / f];
          out.num_occupied += v == 0;
          v = 255;
        }
    }
}

HullPublisher::HullPublisher(bus::Bus& bus, std::string rig_id, const HullPublishOptions& options,
                             Counters& counters)
    : bus_(bus), rig_id_(std::move(rig_id)), options_(options), counters_(counters) {
  HULLPOSE_THROW_UNLESS(options.rate_hz > 0 && options.rate_hz <= 30,
                        "--hull-rate must be in (0, 30] hulls per second, got " << options.rate_hz);
  HULLPOSE_THROW_UNLESS(options.max_dim >= 8 && options.max_dim <= hullpose_msg::hull_t::MAX_DIM,
                        "hull max_dim must be in 8.." << hullpose_msg::hull_t::MAX_DIM << ", got "
                                                      << options.max_dim);
  // A hair under the period, so that "2 Hz" of a 30 Hz trigger takes every 15th frame, not 16th.
  period_us_ = static_cast<int64_t>(1e6 / options.rate_hz) - 1000;
  thread_ = std::thread([this] { work(); });
}

HullPublisher::~HullPublisher() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void HullPublisher::offer(const BitGrid& hull, const VoxelGridSpec& grid, int64_t utime,
                          int64_t trigger_seq) {
  if (last_offered_utime_ != INT64_MIN && utime - last_offered_utime_ < period_us_) return;
  last_offered_utime_ = utime;
  {
    // The worker holds the lock only to swap buffers and set its flags, so this waits for no
    // more than that. (try_lock would not wait, but it fails whenever the worker holds the lock
    // for a moment, a spurious wakeup with nothing to do included, and may fail spuriously
    // besides: under qemu-aarch64 a due hull was dropped as busy with the worker idle.)
    std::unique_lock lock(mutex_);
    if (pending_ || busy_) {
      counters_.add("hull_dropped_busy");
      return;
    }
    slot_.reset(hull.dims());  // reuses the allocation
    std::copy(hull.words().begin(), hull.words().end(), slot_.words().begin());
    slot_spec_ = grid;
    slot_utime_ = utime;
    slot_seq_ = trigger_seq;
    pending_ = true;
  }
  wake_.notify_one();
}

void HullPublisher::drain() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return !pending_ && !busy_; });
}

void HullPublisher::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return pending_ || stop_; });
    if (stop_) return;
    std::swap(slot_, work_grid_);
    work_spec_ = slot_spec_;
    coarse_.utime = slot_utime_;
    coarse_.trigger_seq = slot_seq_;
    pending_ = false;
    busy_ = true;
    lock.unlock();
    coarsen_hull(work_grid_, work_spec_, options_.max_dim, coarse_, row_scratch_);
    msg::to_message(coarse_, rig_id_, encoder_, message_);
    counters_.add(wire::publish(bus_, options_.channel, message_, buffer_) ? "hull_published"
                                                                           : "hull_publish_error");
    lock.lock();
    busy_ = false;
    idle_.notify_all();
  }
}

}  // namespace hullpose::fusion
