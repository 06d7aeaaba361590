#include "hullpose/msg/wire.hpp"

#include <cstring>

namespace hullpose::wire {
namespace {

// LCM encodes big-endian; the 8-byte type fingerprint comes first (the decoder checks it).
class Cursor {
 public:
  explicit Cursor(std::span<const uint8_t> bytes) : p_(bytes.data()), size_(bytes.size()) {}
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
  // An array length field: false (and the cursor failed) unless 0 <= n <= max.
  int32_t count(int32_t max) {
    const int32_t n = i32();
    if (n < 0 || n > max) ok_ = false;
    return ok_ ? n : 0;
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

bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::silhouette_t*) {
  Cursor c(bytes);
  c.skip(8 + 8);                  // fingerprint, utime
  c.string();                     // rig_id
  c.skip(4 + 8 + 8 + 6 * 4 + 1);  // camera_id, trigger_seq, capture_utime, sizes and ROI, encoding
  c.skip(static_cast<size_t>(c.count(kMaxPayload)));
  c.skip(4 * 4 + 8);  // node timings, node_done_utime
  return c.done();
}

bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::trigger_t*) {
  Cursor c(bytes);
  c.skip(8 + 8);
  c.string();
  c.skip(8 + 4 + 4 + 8);  // seq, period_us, pulse_width_us, epoch
  return c.done();
}

bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::skeleton_t*) {
  Cursor c(bytes);
  c.skip(8 + 8);
  c.string();
  c.skip(8 + 4);  // trigger_seq, subject_id
  const int32_t joints = c.count(kMaxJoints);
  for (int32_t i = 0; i < joints && c.ok(); ++i) c.string();
  c.skip(static_cast<size_t>(joints) * (3 * 4 + 4));  // position, confidence
  // valid, reason, model_version, cameras_used_mask, num_cameras_used, latencies
  c.skip(1 + 1 + 4 + 8 + 4 + 5 * 4);
  return c.done();
}

bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::node_status_t*) {
  Cursor c(bytes);
  c.skip(8 + 8);
  c.string();         // rig_id
  c.string();         // role
  c.skip(4);          // node_id
  c.string();         // hostname
  c.skip(1);          // state
  c.string();         // message
  c.skip(4 + 8 + 8);  // fps, frames_total, last_trigger_seq
  const int32_t stages = c.count(kMaxStatusEntries);
  for (int32_t i = 0; i < stages && c.ok(); ++i) c.string();
  c.skip(static_cast<size_t>(stages) * 4);
  const int32_t counters = c.count(kMaxStatusEntries);
  for (int32_t i = 0; i < counters && c.ok(); ++i) c.string();
  c.skip(static_cast<size_t>(counters) * 8);
  return c.done();
}

bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::hull_t*) {
  Cursor c(bytes);
  c.skip(8 + 8);
  c.string();                         // rig_id
  c.skip(8 + 3 * 4 + 3 * 4 + 4 + 4);  // trigger_seq, nx ny nz, origin_mm, voxel_mm, carved_voxel_mm
  c.skip(4 + 1);                      // num_occupied, encoding
  c.skip(static_cast<size_t>(c.count(kMaxPayload)));
  return c.done();
}

}  // namespace hullpose::wire
