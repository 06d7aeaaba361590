#include "hullpose/common/lcm_wire.hpp"

#include <cstring>

namespace hullpose::wire {
namespace {

// LCM encodes big-endian; the 8-byte type fingerprint comes first (the decoder checks it).
class Cursor {
 public:
  Cursor(const void* data, size_t size) : p_(static_cast<const uint8_t*>(data)), size_(size) {}
  bool skip(size_t n) {
    if (!ok_ || n > size_ - pos_) return ok_ = false;
    pos_ += n;
    return true;
  }
  int32_t i32() {
    if (!ok_ || size_ - pos_ < 4) {
      ok_ = false;
      return 0;
    }
    const uint32_t v = (uint32_t{p_[pos_]} << 24) | (uint32_t{p_[pos_ + 1]} << 16) |
                       (uint32_t{p_[pos_ + 2]} << 8) | p_[pos_ + 3];
    pos_ += 4;
    int32_t out;
    std::memcpy(&out, &v, 4);
    return out;
  }
  bool string() {
    const int32_t len = i32();  // includes the terminating NUL
    if (len < 1 || len > kMaxString) return ok_ = false;
    return skip(static_cast<size_t>(len));
  }
  bool done() const { return ok_ && pos_ == size_; }
  bool ok() const { return ok_; }

 private:
  const uint8_t* p_;
  size_t size_;
  size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace

bool silhouette_ok(const void* data, size_t size) {
  Cursor c(data, size);
  c.skip(8 + 8);                  // fingerprint, utime
  c.string();                     // rig_id
  c.skip(4 + 8 + 8 + 6 * 4 + 1);  // camera_id, trigger_seq, capture_utime, sizes and ROI, encoding
  const int32_t payload = c.i32();
  if (payload < 0 || payload > kMaxPayload) return false;
  c.skip(static_cast<size_t>(payload));
  c.skip(4 * 4 + 8);  // node timings, node_done_utime
  return c.done();
}

bool trigger_ok(const void* data, size_t size) {
  Cursor c(data, size);
  c.skip(8 + 8);
  c.string();
  c.skip(8 + 4 + 4 + 8);  // seq, period_us, pulse_width_us, epoch
  return c.done();
}

bool skeleton_ok(const void* data, size_t size) {
  Cursor c(data, size);
  c.skip(8 + 8);
  c.string();
  c.skip(8 + 4);  // trigger_seq, subject_id
  const int32_t joints = c.i32();
  if (joints < 0 || joints > kMaxJoints) return false;
  for (int32_t i = 0; i < joints && c.ok(); ++i) c.string();
  c.skip(static_cast<size_t>(joints) * (3 * 4 + 4));  // position, confidence
  c.skip(1 + 1 + 8 + 4 + 5 * 4);  // valid, reason, cameras_used_mask, num_cameras_used, latencies
  return c.done();
}

bool status_ok(const void* data, size_t size) {
  Cursor c(data, size);
  c.skip(8 + 8);
  c.string();         // rig_id
  c.string();         // role
  c.skip(4);          // node_id
  c.string();         // hostname
  c.skip(1);          // state
  c.string();         // message
  c.skip(4 + 8 + 8);  // fps, frames_total, last_trigger_seq
  const auto named_values = [&c](size_t value_size) {
    const int32_t n = c.i32();
    if (n < 0 || n > kMaxJoints) return false;
    for (int32_t i = 0; i < n && c.ok(); ++i) c.string();
    return c.skip(static_cast<size_t>(n) * value_size);
  };
  return named_values(4) && named_values(8) && c.done();  // stages (float ms), counters (int64)
}

}  // namespace hullpose::wire
