#pragma once
// Gathers the silhouettes of one trigger instant. Messages are keyed by trigger_seq (the rig id
// must be ours); a frame closes when every camera of the rig has arrived, when its deadline
// passes (measured from its first silhouette, or from the trigger announcement in
// DeadlineFrom::kTrigger mode), when a newer frame completes (frames close in sequence order,
// so skeletons never go backwards), or when the cap on open frames forces the oldest out. A
// closed frame goes to the caller with all its views if it has at least min_cameras, and as
// "too few" otherwise; frames announced on TRIGGER that no silhouette ever reached close as
// "no views", so every trigger sequence is fused or accounted for.
//
// Hostile input is expected: every message is checked (rig, camera, sizes against the rig file,
// trigger time against this host's clock and the TRIGGER stream, payload through the codec with
// the camera's size as limit) and a bad one is counted under its reason and dropped. Masks decode
// straight into buffers owned by the frame slots, which are reused: no allocation per frame once
// every slot has been used.
#include <array>
#include <cstdint>
#include <functional>
#include <hullpose_msg/silhouette_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <opencv2/core/mat.hpp>
#include <span>
#include <vector>

#include "hullpose/common/counters.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/common/silhouette_codec.hpp"

namespace hullpose::fusion {

enum class DeadlineFrom { kFirstArrival, kTrigger };

struct AssemblerConfig {
  int min_cameras = 0;           // 0: all cameras but two (at least 1)
  int64_t deadline_us = 33'000;  // about one frame period at 30 Hz
  DeadlineFrom deadline_from = DeadlineFrom::kFirstArrival;
  // A frame known only from its TRIGGER announcement closes this long after it (nodes' latency).
  int64_t no_views_timeout_us = 250'000;
  size_t max_open = 8;  // open frames at most (bounded memory)
  // A silhouette whose utime differs from its frame's by more than this is inconsistent.
  int64_t utime_tolerance_us = 5'000;
  // Without a TRIGGER stream to check against, trigger times further than this from this
  // host's clock are implausible (master and host clocks are assumed synchronised to well
  // within it: NTP/PTP on a real rig).
  int64_t max_clock_skew_us = 2'000'000;
};

struct View {
  int camera_id = 0;
  int camera_index = 0;           // index into Rig::cameras
  const cv::Mat* mask = nullptr;  // CV_8UC1, full image, 255 = person
  PixelRoi roi;
  int64_t capture_utime = 0;    // master clock
  int64_t node_done_utime = 0;  // master clock
  int64_t received_utime = 0;   // this host's clock
};

enum class FrameStatus { kComplete, kPartial, kTooFew };

struct AssembledFrame {
  int64_t trigger_seq = 0;
  int64_t utime = 0;  // trigger instant, master clock
  FrameStatus status = FrameStatus::kComplete;
  std::span<const View> views;  // valid during the callback only
  uint64_t camera_mask = 0;     // bit i: camera id i
  int64_t last_received_utime = 0;
};

class FrameAssembler {
 public:
  using OnFrame = std::function<void(const AssembledFrame&)>;
  // The rig must be valid (load_rig validates); throws hullpose::Error on a bad config.
  // on_frame receives every closed frame, from poll() or from a message that forced a close.
  FrameAssembler(const Rig& rig, const AssemblerConfig& config, OnFrame on_frame);

  // now_us: this host's monotonic clock; received_utime: this host's realtime at arrival.
  void on_bytes(std::span<const uint8_t> lcm_bytes, int64_t received_utime, int64_t now_us);
  void on_silhouette(const hullpose_msg::silhouette_t& msg, int64_t received_utime, int64_t now_us);
  void on_trigger(const hullpose_msg::trigger_t& msg, int64_t now_us);
  // Closes every frame that is ready at now_us, oldest first.
  void poll(int64_t now_us);
  // Closes every open frame (shutdown, master restart).
  void flush();

  int min_cameras() const { return min_cameras_; }
  size_t open_frames() const;
  // Drops: foreign_rig, unknown_camera, malformed_lcm, bad_encoding, wrong_size, bad_fields,
  // decode_error, implausible_time, inconsistent_utime, duplicate, late, capacity, seq_restart,
  // epoch_change (TRIGGER), stale_epoch_trigger, bad_trigger, foreign_rig_trigger. Frames:
  // fused_complete, fused_partial, too_few_cameras, no_views.
  const Counters& counters() const { return counters_; }

 private:
  struct Slot {
    bool open = false;
    int64_t seq = 0, utime = 0;
    int64_t reference_us = 0;  // deadline reference (monotonic)
    bool has_reference = false;
    bool from_trigger_only = true;
    int present = 0;
    uint64_t camera_mask = 0;
    int64_t last_received_utime = 0;
    std::vector<View> views;     // per camera index
    std::vector<char> has;       // per camera index
    std::vector<cv::Mat> masks;  // per camera index, reused
  };
  // The open slot of seq, a newly opened one, or nullptr (counted late).
  Slot* find_or_open(int64_t seq, int64_t utime);
  void close(Slot& slot);
  void close_older_than(int64_t seq);
  bool due(const Slot& slot, int64_t now_us) const;
  bool plausible(int64_t seq, int64_t utime, int64_t received_utime, int64_t now_us) const;

  // Recent TRIGGER announcements (slot seq % kTriggerRing): a silhouette must fit the stream.
  struct LastTrigger {
    int64_t seq = -1, utime = 0, period_us = 0;
  };
  static constexpr size_t kTriggerRing = 64;
  std::array<LastTrigger, kTriggerRing> triggers_{};
  int64_t newest_trigger_ = -1;
  int64_t newest_trigger_at_us_ = 0;
  int64_t epoch_ = 0, retired_epoch_ = 0;  // of the TRIGGER stream
  static constexpr int64_t kRestartGapUs = 500'000;

  const Rig& rig_;
  AssemblerConfig config_;
  int min_cameras_;
  std::vector<Slot> slots_;
  std::vector<View> scratch_;
  hullpose_msg::silhouette_t msg_;  // decode target for on_bytes, reused
  int64_t high_seq_ = -1;           // newest closed sequence
  int64_t high_utime_ = 0;
  OnFrame on_frame_;
  Counters counters_;
};

}  // namespace hullpose::fusion
