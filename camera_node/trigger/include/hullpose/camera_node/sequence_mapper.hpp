#pragma once
// Maps trigger edges seen by a camera node to the sequence numbers the trigger master announced.
//
// The node knows an edge only by its own clock; an announcement carries the edge time on the
// master's clock (utime) and arrives over the network a little after the edge. The boards'
// clocks may differ by any amount (seconds), so the mapper first learns the offset
// node - master: each announcement is paired with the latest edge before its arrival, if that
// edge is no older than max_latency; the median over the recent pairs is the offset (a minority
// of wrong pairs, from lost edges or delayed announcements, is off by whole periods and does
// not move the median). With the offset, an edge maps to the announcement whose utime is within
// a quarter period of it. An edge whose announcement was lost is interpolated between two
// announcements whose spacing matches their sequence numbers (so a master that skipped slots is
// never guessed across); it is never extrapolated past the newest announcement, since the
// master may have skipped a slot there: such an edge waits for the next announcement. An
// epoch change (master restarted) forgets the announcements and starts over.
//
// Pure logic: times in, results out, bounded memory, no allocation after construction.
#include <cstdint>
#include <vector>

#include "hullpose/common/counters.hpp"

namespace hullpose::trigger {

struct Announcement {
  int64_t seq = 0;
  int64_t utime = 0;  // master clock
  int64_t epoch = 0;
  int64_t period_us = 0;
  int64_t received_us = 0;  // node clock
};

struct MappedEdge {
  int64_t edge_us = 0;  // node clock
  int64_t seq = 0;
  int64_t utime = 0;  // the trigger instant on the master clock (announced or interpolated)
  int64_t epoch = 0;
  int64_t offset_us = 0;  // node clock - master clock at the time of mapping
  bool interpolated = false;
};

struct MapperConfig {
  int64_t max_latency_us = 15'000;  // announcement arrival after its edge, for offset pairing
  int64_t hold_us = 200'000;  // an edge with no announcement at or after it by then is dropped
  int64_t sync_timeout_us = 2'000'000;  // an edge older than this without an offset is dropped
  static constexpr size_t kAnnouncements = 64;
  static constexpr size_t kEdges = 64;
  static constexpr size_t kOffsetPairs = 33;
};

class SequenceMapper {
 public:
  explicit SequenceMapper(const MapperConfig& config = {});

  void on_announcement(const Announcement& a);
  void on_edge(int64_t edge_us);
  // Appends every edge that can be decided by now (node clock) to `out`, oldest first; edges
  // that cannot be mapped are counted ("no_sync", "unmatched", "duplicate_edge",
  // "epoch_change", "edge_overflow") and dropped.
  void poll(int64_t now_us, std::vector<MappedEdge>& out);

  bool synced() const { return have_offset_; }
  size_t pending_edges() const { return pending_.size(); }
  int64_t offset_us() const { return offset_us_; }
  int64_t epoch() const { return epoch_; }
  const Counters& counters() const { return counters_; }

 private:
  void update_offset();
  // The announcement for master time m (exact, interpolated or extrapolated), false if none fits.
  bool map_time(int64_t m, MappedEdge& e) const;

  MapperConfig config_;
  std::vector<Announcement> ann_;  // sorted by seq, at most kAnnouncements
  std::vector<int64_t> history_;   // recent edge times (ring), for offset pairing
  size_t history_next_ = 0;
  std::vector<int64_t> pending_;  // edges not yet mapped, oldest first
  std::vector<int64_t> pairs_;    // scratch for the median
  int64_t epoch_ = 0;
  int64_t retired_epoch_ = 0;  // announcements of the previous master run are stale
  bool have_offset_ = false;
  bool offset_dirty_ = false;
  int64_t offset_us_ = 0;
  int64_t last_seq_ = -1;
  Counters counters_;
};

}  // namespace hullpose::trigger
