#include "hullpose/fusion_host/frame_assembler.hpp"

#include <algorithm>
#include <cstdlib>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/msg/wire.hpp"

namespace hullpose::fusion {
HULLPOSE_LOG_CATEGORY(Assembly, "assembly")

FrameAssembler::FrameAssembler(const Rig& rig, const AssemblerConfig& config, OnFrame on_frame)
    : rig_(rig), config_(config), on_frame_(std::move(on_frame)) {
  const int n = static_cast<int>(rig.cameras.size());
  HULLPOSE_THROW_UNLESS(n > 0, "frame assembly: rig '" << rig.rig_id << "' has no cameras");
  min_cameras_ = config.min_cameras > 0 ? config.min_cameras : std::max(1, n - 2);
  HULLPOSE_THROW_UNLESS(min_cameras_ <= n, "frame assembly: min_cameras "
                                               << config.min_cameras << " exceeds the " << n
                                               << " cameras of rig '" << rig.rig_id << "'");
  HULLPOSE_THROW_UNLESS(config.deadline_us > 0, "frame assembly: deadline must be positive, got "
                                                    << config.deadline_us << " us");
  HULLPOSE_THROW_UNLESS(config.max_open >= 1 && config.max_open <= 256,
                        "frame assembly: max_open " << config.max_open << " outside 1..256");
  slots_.resize(config.max_open);
  for (Slot& s : slots_) {
    s.views.resize(static_cast<size_t>(n));
    s.has.assign(static_cast<size_t>(n), 0);
    s.masks.resize(static_cast<size_t>(n));
  }
  scratch_.reserve(static_cast<size_t>(n));
}

size_t FrameAssembler::open_frames() const {
  return static_cast<size_t>(
      std::count_if(slots_.begin(), slots_.end(), [](const Slot& s) { return s.open; }));
}

void FrameAssembler::on_bytes(std::span<const uint8_t> lcm_bytes, int64_t received_utime,
                              int64_t now_us) {
  if (!wire::decode(lcm_bytes, msg_)) {
    counters_.add("malformed_lcm");
    HULLPOSE_LOG(Assembly, Debug) << "dropped a SILHOUETTE message that is not a silhouette_t ("
                                  << lcm_bytes.size() << " bytes)";
    return;
  }
  on_silhouette(msg_, received_utime, now_us);
}

void FrameAssembler::on_silhouette(const hullpose_msg::silhouette_t& m, int64_t received_utime,
                                   int64_t now_us) {
  auto drop = [&](const char* reason) {
    counters_.add(reason);
    HULLPOSE_LOG(Assembly, Debug) << "dropped silhouette camera " << m.camera_id << " seq "
                                  << m.trigger_seq << ": " << reason;
  };
  if (m.rig_id != rig_.rig_id) return drop("foreign_rig");
  const CameraModel* cam = rig_.find(m.camera_id);
  if (!cam) return drop("unknown_camera");
  if (m.encoding != hullpose_msg::silhouette_t::ENCODING_RLE_V1) return drop("bad_encoding");
  if (m.width != cam->width || m.height != cam->height) return drop("wrong_size");
  if (m.payload_size != static_cast<int32_t>(m.payload.size()) || m.trigger_seq < 0 || m.utime <= 0)
    return drop("bad_fields");

  if (!plausible(m.trigger_seq, m.utime, received_utime, now_us)) return drop("implausible_time");
  Slot* slot = find_or_open(m.trigger_seq, m.utime);
  if (!slot) return drop("late");
  if (std::llabs(m.utime - slot->utime) > config_.utime_tolerance_us)
    return drop("inconsistent_utime");
  const auto index = static_cast<size_t>(cam - rig_.cameras.data());
  if (slot->has[index]) return drop("duplicate");

  SilhouetteHeader header;
  const CodecError err = decode_silhouette(m.payload, DecodeLimits{cam->width, cam->height},
                                           slot->masks[index], &header);
  if (err != CodecError::kNone) {
    counters_.add("decode_error");
    HULLPOSE_LOG(Assembly, Debug) << "camera " << m.camera_id << " seq " << m.trigger_seq << ": "
                                  << to_string(err);
    return;
  }
  if (header.width != cam->width || header.height != cam->height) return drop("wrong_size");
  if (header.roi != PixelRoi{m.roi_x, m.roi_y, m.roi_width, m.roi_height})
    return drop("bad_fields");

  slot->has[index] = 1;
  slot->views[index] =
      View{m.camera_id,     static_cast<int>(index), &slot->masks[index], header.roi,
           m.capture_utime, m.node_done_utime,       received_utime};
  ++slot->present;
  slot->camera_mask |= uint64_t{1} << m.camera_id;
  slot->last_received_utime = std::max(slot->last_received_utime, received_utime);
  if (!slot->has_reference ||
      (slot->from_trigger_only && config_.deadline_from == DeadlineFrom::kFirstArrival)) {
    slot->reference_us = now_us;
    slot->has_reference = true;
  }
  slot->from_trigger_only = false;
  if (slot->present == static_cast<int>(rig_.cameras.size())) {
    close_older_than(slot->seq);
    close(*slot);
  }
}

void FrameAssembler::on_trigger(const hullpose_msg::trigger_t& t, int64_t now_us) {
  if (t.rig_id != rig_.rig_id) {
    counters_.add("foreign_rig_trigger");
    return;
  }
  if (t.seq < 0 || t.utime <= 0 || t.period_us <= 0 || t.epoch == 0) {
    counters_.add("bad_trigger");
    return;
  }
  if (t.epoch != epoch_) {
    if (t.epoch == retired_epoch_) {  // a late announcement of the master's previous run
      counters_.add("stale_epoch_trigger");
      return;
    }
    if (epoch_ != 0) {
      // The master restarted: its sequence counts from 0 again. The open frames belong to the
      // old run: close them now, so that their sequences cannot make the new ones look late.
      HULLPOSE_LOG(Assembly, Info)
          << "trigger epoch " << epoch_ << " -> " << t.epoch << ": master restarted";
      counters_.add("epoch_change");
      flush();
      high_seq_ = -1;
      triggers_.fill({});
      newest_trigger_ = -1;
    }
    retired_epoch_ = epoch_;
    epoch_ = t.epoch;
  }
  {
    triggers_[static_cast<size_t>(t.seq) % kTriggerRing] = {t.seq, t.utime, t.period_us};
    if (t.seq > newest_trigger_ || now_us - newest_trigger_at_us_ > 1'000'000)
      newest_trigger_ = t.seq;
    newest_trigger_at_us_ = now_us;
  }
  Slot* slot = find_or_open(t.seq, t.utime);
  if (!slot || slot->present > 0) return;
  if (!slot->has_reference) {
    slot->reference_us = now_us;
    slot->has_reference = true;
  }
}

FrameAssembler::Slot* FrameAssembler::find_or_open(int64_t seq, int64_t utime) {
  for (Slot& s : slots_)
    if (s.open && s.seq == seq) return &s;
  // A new frame must be newer than every closed one. Within one master run sequence and trigger
  // time grow together; an older sequence with a clearly newer time means the master restarted
  // (a restart takes far longer than kRestartGapUs; a slightly newer time is a bad message).
  if (utime <= high_utime_) return nullptr;
  if (seq <= high_seq_) {
    if (utime < high_utime_ + kRestartGapUs) return nullptr;
    HULLPOSE_LOG(Assembly, Info) << "trigger sequence restarted (" << high_seq_ << " -> " << seq
                                 << "): master restart";
    counters_.add("seq_restart");
    high_seq_ = -1;
  }
  Slot* free = nullptr;
  for (Slot& s : slots_)
    if (!s.open) {
      free = &s;
      break;
    }
  if (!free) {
    Slot* oldest = &slots_.front();
    for (Slot& s : slots_)
      if (s.seq < oldest->seq) oldest = &s;
    if (oldest->seq > seq) return nullptr;  // older than everything we hold: late
    counters_.add("capacity");
    close(*oldest);
    free = oldest;
  }
  free->open = true;
  free->seq = seq;
  free->utime = utime;
  free->has_reference = false;
  free->from_trigger_only = true;
  free->present = 0;
  free->camera_mask = 0;
  free->last_received_utime = 0;
  std::fill(free->has.begin(), free->has.end(), 0);
  return free;
}

bool FrameAssembler::plausible(int64_t seq, int64_t utime, int64_t received_utime,
                               int64_t now_us) const {
  // One bogus frame far in the future would make every real one "late": while announcements
  // flow, the trigger time must fit the announced ones (the master's own pulse jitter can reach
  // tens of ms under load, so the bounds come from announced times, not the nominal grid);
  // otherwise it is bounded by this host's clock. (A replayed log brings its TRIGGER stream
  // along, so old trigger times pass.)
  if (newest_trigger_ < 0 || now_us - newest_trigger_at_us_ > 1'000'000)
    return std::llabs(utime - received_utime) <= config_.max_clock_skew_us;
  const LastTrigger& newest = triggers_[static_cast<size_t>(newest_trigger_) % kTriggerRing];
  const LastTrigger& same = triggers_[static_cast<size_t>(seq) % kTriggerRing];
  if (same.period_us > 0 && same.seq == seq)
    return std::llabs(utime - same.utime) <= same.period_us / 2;
  if (seq > newest.seq) {
    const int64_t steps = seq - newest.seq;
    return steps <= 2 && utime > newest.utime &&
           utime <= newest.utime + (steps + 1) * newest.period_us;
  }
  // An announcement this host missed: between its neighbours in time.
  const LastTrigger* lo = nullptr;
  const LastTrigger* hi = nullptr;
  for (const LastTrigger& t : triggers_) {
    if (t.period_us <= 0 || newest.seq - t.seq >= static_cast<int64_t>(kTriggerRing)) continue;
    if (t.seq < seq && (!lo || t.seq > lo->seq)) lo = &t;
    if (t.seq > seq && (!hi || t.seq < hi->seq)) hi = &t;
  }
  if (!hi) return false;
  if (!lo)  // older than every announcement seen (this host just started): bounded from above
    return utime < hi->utime && hi->utime - utime <= (hi->seq - seq + 1) * hi->period_us;
  return utime > lo->utime && utime < hi->utime;
}

bool FrameAssembler::due(const Slot& s, int64_t now_us) const {
  if (!s.has_reference) return false;
  const int64_t wait = s.present == 0 ? config_.no_views_timeout_us : config_.deadline_us;
  return now_us - s.reference_us >= wait;
}

void FrameAssembler::poll(int64_t now_us) {
  for (;;) {
    Slot* oldest_due = nullptr;
    for (Slot& s : slots_)
      if (s.open && due(s, now_us) && (!oldest_due || s.seq < oldest_due->seq)) oldest_due = &s;
    if (!oldest_due) return;
    close_older_than(oldest_due->seq);
    close(*oldest_due);
  }
}

void FrameAssembler::flush() {
  for (;;) {
    Slot* oldest = nullptr;
    for (Slot& s : slots_)
      if (s.open && (!oldest || s.seq < oldest->seq)) oldest = &s;
    if (!oldest) return;
    close(*oldest);
  }
}

void FrameAssembler::close_older_than(int64_t seq) {
  for (;;) {
    Slot* oldest = nullptr;
    for (Slot& s : slots_)
      if (s.open && s.seq < seq && (!oldest || s.seq < oldest->seq)) oldest = &s;
    if (!oldest) return;
    close(*oldest);
  }
}

void FrameAssembler::close(Slot& slot) {
  HULLPOSE_ASSERT(slot.open);
  slot.open = false;
  if (slot.seq > high_seq_) {
    high_seq_ = slot.seq;
    high_utime_ = slot.utime;
  }
  scratch_.clear();
  for (size_t i = 0; i < slot.views.size(); ++i)
    if (slot.has[i]) scratch_.push_back(slot.views[i]);
  AssembledFrame f;
  f.trigger_seq = slot.seq;
  f.utime = slot.utime;
  f.views = scratch_;
  f.camera_mask = slot.camera_mask;
  f.last_received_utime = slot.last_received_utime;
  if (slot.present == static_cast<int>(rig_.cameras.size())) {
    f.status = FrameStatus::kComplete;
    counters_.add("fused_complete");
  } else if (slot.present >= min_cameras_) {
    f.status = FrameStatus::kPartial;
    counters_.add("fused_partial");
  } else {
    f.status = FrameStatus::kTooFew;
    counters_.add(slot.present == 0 ? "no_views" : "too_few_cameras");
    HULLPOSE_LOG(Assembly, Debug) << "seq " << slot.seq << ": " << slot.present << " of "
                                  << rig_.cameras.size() << " cameras, below min_cameras "
                                  << min_cameras_;
  }
  on_frame_(f);
}

}  // namespace hullpose::fusion
