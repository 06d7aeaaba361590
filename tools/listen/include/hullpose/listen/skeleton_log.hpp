#pragma once
// What hullpose-listen does with each skeleton: write it as a CSV row or a JSON line, and keep
// latency statistics per stage of the breakdown (trigger -> capture -> node done -> received
// -> fused -> published) plus counts of valid / invalid skeletons by reason and of sequence
// numbers never received.
#include <array>
#include <cstdint>
#include <hullpose_msg/skeleton_t.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace hullpose::listen {

// Percentiles over the last kCapacity samples (a preallocated ring).
class LatencySeries {
 public:
  static constexpr size_t kCapacity = 1 << 18;
  LatencySeries() { samples_.reserve(kCapacity); }
  void add(int32_t us);
  size_t count() const { return total_; }
  // q in [0, 1]; 0 when empty. Sorts a copy: for summaries, not per message.
  double percentile_ms(double q) const;
  double max_ms() const;

 private:
  std::vector<int32_t> samples_;
  size_t next_ = 0, total_ = 0;
};

inline constexpr std::array<const char*, 5> kStages = {"capture", "node_done", "received", "fused",
                                                       "published"};

class SkeletonStats {
 public:
  void add(const hullpose_msg::skeleton_t& s);
  int64_t received() const { return received_; }
  int64_t valid() const { return valid_; }
  int64_t missing_sequences() const { return missing_; }
  const LatencySeries& stage(size_t i) const { return stages_[i]; }
  // One JSON object: counts, reasons, per-stage p50 / p99 / max in ms.
  std::string summary_json() const;

 private:
  std::array<LatencySeries, kStages.size()> stages_;
  std::array<int64_t, 8> reasons_{};  // by REASON_* code; the last one also counts larger codes
  int64_t received_ = 0, valid_ = 0, missing_ = 0, out_of_order_ = 0, last_seq_ = -1;
};

void write_csv_header(std::ostream& out);
void write_csv(std::ostream& out, const hullpose_msg::skeleton_t& s);
void write_jsonl(std::ostream& out, const hullpose_msg::skeleton_t& s);
// docs/conventions.md estimate file (read by hullpose-eval): frame = trigger_seq - frame_offset.
void write_estimate_header(std::ostream& out);
void write_estimate(std::ostream& out, const hullpose_msg::skeleton_t& s, int64_t frame_offset);

}  // namespace hullpose::listen
