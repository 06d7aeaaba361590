#include "hullpose/camera_node/sequence_mapper.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "hullpose/common/log.hpp"

namespace hullpose::trigger {
HULLPOSE_LOG_CATEGORY(Mapper, "trigger")

namespace {
constexpr size_t kMinPairs = 3;  // pairs before the first offset is trusted
int64_t round_div(int64_t num, int64_t den) {
  return static_cast<int64_t>(std::llround(static_cast<double>(num) / static_cast<double>(den)));
}
}  // namespace

SequenceMapper::SequenceMapper(const MapperConfig& config) : config_(config) {
  ann_.reserve(MapperConfig::kAnnouncements + 1);
  history_.reserve(MapperConfig::kEdges);
  pending_.reserve(MapperConfig::kEdges);
  pairs_.reserve(MapperConfig::kAnnouncements);
}

void SequenceMapper::on_announcement(const Announcement& a) {
  // 0.1 Hz .. 1 kHz, as the trigger master allows: anything else is not a trigger announcement.
  if (a.period_us < 1'000 || a.period_us > 10'000'000 || a.seq < 0 || a.epoch == 0) {
    counters_.add("bad_announcement");
    return;
  }
  if (a.epoch != epoch_) {
    if (a.epoch == retired_epoch_) {
      counters_.add("stale_epoch");
      return;
    }
    if (epoch_ != 0) {
      HULLPOSE_LOG(Mapper, Info) << "trigger epoch " << epoch_ << " -> " << a.epoch
                                 << ": resynchronising";
      counters_.add("epoch_change");
    }
    retired_epoch_ = epoch_;
    epoch_ = a.epoch;
    ann_.clear();
    last_seq_ = -1;
  }
  auto it = std::lower_bound(ann_.begin(), ann_.end(), a.seq,
                             [](const Announcement& x, int64_t seq) { return x.seq < seq; });
  if (it != ann_.end() && it->seq == a.seq) {
    counters_.add("duplicate_announcement");
    return;
  }
  if (ann_.size() == MapperConfig::kAnnouncements) {
    if (it == ann_.begin()) return;  // older than everything we keep
    ann_.erase(ann_.begin());
    it = std::lower_bound(ann_.begin(), ann_.end(), a.seq,
                          [](const Announcement& x, int64_t seq) { return x.seq < seq; });
  }
  ann_.insert(it, a);
  offset_dirty_ = true;
}

void SequenceMapper::on_edge(int64_t edge_us) {
  if (history_.size() < MapperConfig::kEdges) {
    history_.push_back(edge_us);
  } else {
    history_[history_next_] = edge_us;
    history_next_ = (history_next_ + 1) % MapperConfig::kEdges;
  }
  if (pending_.size() == MapperConfig::kEdges) {
    pending_.erase(pending_.begin());
    counters_.add("edge_overflow");
  }
  pending_.push_back(edge_us);
  offset_dirty_ = true;
}

void SequenceMapper::update_offset() {
  offset_dirty_ = false;
  pairs_.clear();
  for (const Announcement& a : ann_) {
    const int64_t max_latency = std::min(config_.max_latency_us, a.period_us / 2);
    bool found = false;
    int64_t latest = 0;
    for (int64_t e : history_) {
      if (e <= a.received_us && (!found || e > latest)) {
        latest = e;
        found = true;
      }
    }
    if (found && a.received_us - latest <= max_latency) pairs_.push_back(latest - a.utime);
  }
  if (pairs_.size() < (have_offset_ ? size_t{1} : kMinPairs)) return;
  const auto mid = pairs_.begin() + static_cast<std::ptrdiff_t>(pairs_.size() / 2);
  std::nth_element(pairs_.begin(), mid, pairs_.end());
  if (!have_offset_) {
    HULLPOSE_LOG(Mapper, Info) << "synchronised: node clock - master clock = " << *mid << " us";
  }
  offset_us_ = *mid;
  have_offset_ = true;
}

bool SequenceMapper::map_time(int64_t m, MappedEdge& e) const {
  const Announcement* lo = nullptr;
  const Announcement* hi = nullptr;
  for (const Announcement& a : ann_) {
    if (std::llabs(a.utime - m) <= a.period_us / 4) {
      e.seq = a.seq;
      e.utime = a.utime;
      e.interpolated = false;
      return true;
    }
    if (a.utime < m) {
      lo = &a;
    } else if (!hi) {
      hi = &a;
    }
  }
  // Interpolate only between announcements whose spacing matches their sequence numbers, so a
  // master that skipped slots is never guessed across; never extrapolate past the newest.
  if (!lo || !hi) return false;
  const int64_t period = lo->period_us;
  const int64_t steps = hi->seq - lo->seq;
  if (hi->period_us != period || std::llabs(hi->utime - lo->utime - steps * period) > period / 4)
    return false;
  const int64_t n = round_div(m - lo->utime, period);
  if (n <= 0 || n >= steps || std::llabs(m - lo->utime - n * period) > period / 4) return false;
  e.seq = lo->seq + n;
  e.utime = lo->utime + n * period;
  e.interpolated = true;
  return true;
}

void SequenceMapper::poll(int64_t now_us, std::vector<MappedEdge>& out) {
  if (offset_dirty_) update_offset();
  size_t done = 0;
  for (; done < pending_.size(); ++done) {
    const int64_t edge = pending_[done];
    if (!have_offset_) {
      if (now_us - edge > config_.sync_timeout_us) {
        counters_.add("no_sync");
        continue;
      }
      break;
    }
    MappedEdge e;
    e.edge_us = edge;
    e.epoch = epoch_;
    e.offset_us = offset_us_;
    if (!map_time(edge - offset_us_, e)) {
      if (now_us - edge < config_.hold_us) break;  // its announcement may still come
      counters_.add("unmatched");
      HULLPOSE_LOG(Mapper, Debug) << "edge at " << edge << " matches no announcement";
      continue;
    }
    if (e.seq <= last_seq_) {
      counters_.add("duplicate_edge");
      continue;
    }
    last_seq_ = e.seq;
    if (e.interpolated) counters_.add("interpolated");
    out.push_back(e);
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(done));
}

}  // namespace hullpose::trigger
