#include "hullpose/firmware_sync/trigger_master.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose::sync {
HULLPOSE_LOG_CATEGORY(Master, "trigger_master")

void TriggerMasterConfig::validate() const {
  HULLPOSE_THROW_UNLESS(!rig_id.empty(), "trigger master: rig_id is empty");
  HULLPOSE_THROW_UNLESS(std::isfinite(rate_hz) && rate_hz >= 0.1 && rate_hz <= 1000,
                        "trigger master: rate " << rate_hz << " Hz outside 0.1..1000");
  HULLPOSE_THROW_UNLESS(pulse_width_us > 0 && pulse_width_us < period_from_rate(rate_hz),
                        "trigger master: pulse width "
                            << pulse_width_us << " us must be positive and shorter than the period "
                            << period_from_rate(rate_hz) << " us");
}

int64_t period_from_rate(double rate_hz) {
  return std::llround(1e6 / rate_hz);
}

int64_t new_epoch() {
  std::random_device rd;
  const int64_t e = (static_cast<int64_t>(rd()) << 31) ^ static_cast<int64_t>(rd());
  return e == 0 ? 1 : std::abs(e);
}

void JitterStats::add(int64_t late_us) {
  window_[static_cast<size_t>(count_) % kWindow] = std::abs(late_us);
  ++count_;
  sum_ += late_us;
  max_ = std::max(max_, std::abs(late_us));
}

int64_t JitterStats::p99_us() {
  const size_t n = std::min(static_cast<size_t>(count_), kWindow);
  if (n == 0) return 0;
  std::copy_n(window_.begin(), n, scratch_.begin());
  const size_t k = std::min(n - 1, (n * 99) / 100);
  std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(k),
                   scratch_.begin() + static_cast<std::ptrdiff_t>(n));
  return scratch_[k];
}

TriggerMaster::TriggerMaster(const TriggerMasterConfig& config, TriggerLine& line, Clock& clock,
                             Announce announce, int64_t epoch)
    : config_(config),
      line_(line),
      clock_(clock),
      announce_(std::move(announce)),
      epoch_(epoch),
      period_us_(period_from_rate(config.rate_hz)) {
  config_.validate();
  msg_.rig_id = config_.rig_id;
  msg_.epoch = epoch_;
  msg_.pulse_width_us = config_.pulse_width_us;
}

int64_t TriggerMaster::pulse() {
  const int64_t period = period_us_.load();
  const int64_t now = clock_.monotonic_us();
  if (reschedule_.exchange(false)) next_edge_us_ = -1;
  if (next_edge_us_ < 0) next_edge_us_ = now + period;
  // Woke up so late that whole slots passed: skip them, keeping the phase of the pulse train.
  if (now > next_edge_us_ + period / 2) {
    const int64_t skipped = (now - next_edge_us_) / period + 1;
    missed_slots_ += skipped;
    next_edge_us_ += skipped * period;
    HULLPOSE_LOG(Master, Warn) << "overrun: skipped " << skipped << " trigger slot(s) before seq "
                               << seq_;
  }
  clock_.sleep_until_monotonic_us(next_edge_us_);
  const int64_t stamped = line_.set(true);
  const int64_t edge_mono = stamped >= 0 ? stamped : clock_.monotonic_us();
  // The announced utime is the edge's own instant on the realtime clock. Reading the realtime
  // clock after set() instead would add any preemption in between (milliseconds on a loaded
  // machine), and nodes would map the edge to no trigger, or to the wrong one.
  const int64_t realtime_minus_mono = clock_.realtime_utime() - clock_.monotonic_us();
  const int64_t edge_utime = edge_mono + realtime_minus_mono;
  jitter_.add(edge_mono - next_edge_us_);

  msg_.utime = edge_utime;
  msg_.seq = seq_;
  msg_.period_us = static_cast<int32_t>(period);
  announce_(msg_);

  clock_.sleep_until_monotonic_us(next_edge_us_ + config_.pulse_width_us);
  line_.set(false);
  next_edge_us_ += period;
  return seq_++;
}

void TriggerMaster::run(const std::function<bool()>& keep_going) {
  while (keep_going()) {
    if (running_.load()) {
      pulse();
      continue;
    }
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, std::chrono::milliseconds(100), [&] { return running_.load(); });
  }
}

void TriggerMaster::start() {
  {
    std::lock_guard lock(mutex_);
    if (!running_.exchange(true)) reschedule_ = true;
  }
  wake_.notify_all();
}

void TriggerMaster::stop() {
  running_ = false;
}

void TriggerMaster::set_rate(double rate_hz) {
  TriggerMasterConfig c = config_;
  c.rate_hz = rate_hz;
  c.validate();
  period_us_ = period_from_rate(rate_hz);
  HULLPOSE_LOG(Master, Info) << "rate " << rate_hz << " Hz from seq " << seq_;
}

}  // namespace hullpose::sync
