#pragma once
// The optional HULL channel (hull_t, docs/messages.md; off unless --hull-rate HZ): the carved
// hull of a frame, coarsened to at most max_dim voxels a side and compressed (hullpose/msg/
// hull.hpp), for live views. It must never slow the frame loop: offer() only copies the hull's
// words into a one-slot mailbox (256 KiB at 128³, no allocation once sized) when a hull is due
// by the trigger clock; a worker thread coarsens, encodes and publishes it on the process's bus
// (so it is authenticated like everything else). A due hull that finds the worker still busy is
// dropped and counted ("hull_dropped_busy"): at most one waits, whatever the rate.
#include <condition_variable>
#include <cstdint>
#include <hullpose_msg/hull_t.hpp>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/msg/hull.hpp"

namespace hullpose::fusion {

struct HullPublishOptions {
  double rate_hz = 0;  // hulls per second of trigger time; 0: none (no thread either)
  std::string channel = "HULL";
  int max_dim = hullpose_msg::hull_t::MAX_DIM;  // coarse voxels along the longest side, <= MAX_DIM
};

// The coarse hull of `fine` (voxels of `grid`): the smallest whole factor f that brings every
// side to <= max_dim; a coarse voxel is occupied when any of its f³ fine voxels is, so thin limbs
// stay visible. Reuses out.occupancy and `scratch` (one fine row).
void coarsen_hull(const BitGrid& fine, const VoxelGridSpec& grid, int max_dim, msg::CoarseHull& out,
                  std::vector<uint64_t>& scratch);

class HullPublisher {
 public:
  // `bus` and `counters` outlive this. Throws hullpose::Error on options out of range.
  HullPublisher(bus::Bus& bus, std::string rig_id, const HullPublishOptions& options,
                Counters& counters);
  ~HullPublisher();
  HullPublisher(const HullPublisher&) = delete;
  HullPublisher& operator=(const HullPublisher&) = delete;

  // Frame loop: hands the hull of trigger instant `utime` to the worker if one is due (the first,
  // then one per 1/rate of trigger time) and the worker is idle; never waits for the worker's
  // coarsening and publishing.
  void offer(const BitGrid& hull, const VoxelGridSpec& grid, int64_t utime, int64_t trigger_seq);
  // Returns once the worker has published what it was handed (tests; before shutdown).
  void drain();

 private:
  void work();

  bus::Bus& bus_;
  std::string rig_id_;
  HullPublishOptions options_;
  Counters& counters_;
  int64_t period_us_;
  int64_t last_offered_utime_ = INT64_MIN;
  std::mutex mutex_;
  std::condition_variable wake_, idle_;
  bool pending_ = false, busy_ = false, stop_ = false;
  // The mailbox (frame loop writes under mutex_ when !pending_ && !busy_) and the worker's own.
  BitGrid slot_, work_grid_;
  VoxelGridSpec slot_spec_, work_spec_;
  int64_t slot_utime_ = 0, slot_seq_ = 0;
  msg::CoarseHull coarse_;
  std::vector<uint64_t> row_scratch_;
  SilhouetteEncoder encoder_;
  hullpose_msg::hull_t message_;
  std::vector<uint8_t> buffer_;
  std::thread thread_;
};

}  // namespace hullpose::fusion
