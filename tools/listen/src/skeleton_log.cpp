#include "hullpose/listen/skeleton_log.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "hullpose/common/joints.hpp"
#include "hullpose/msg/reasons.hpp"

namespace hullpose::listen {

void LatencySeries::add(int32_t us) {
  samples_[next_] = us;
  next_ = (next_ + 1) % kCapacity;
  filled_ = std::min(filled_ + 1, kCapacity);
  ++total_;
}

double LatencySeries::percentile_ms(double q) const {
  if (filled_ == 0) return 0;
  std::vector<int32_t> v(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(filled_));
  const auto k = static_cast<size_t>(std::min<double>(
      static_cast<double>(v.size() - 1), std::floor(q * static_cast<double>(v.size()))));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k] / 1000.0;
}

double LatencySeries::max_ms() const {
  return filled_ == 0 ? 0
                      : *std::max_element(samples_.begin(),
                                          samples_.begin() + static_cast<std::ptrdiff_t>(filled_)) /
                            1000.0;
}

void SkeletonStats::add(const hullpose_msg::skeleton_t& s) {
  ++received_;
  if (s.valid) ++valid_;
  reasons_[static_cast<size_t>(
      std::clamp<int>(s.reason, 0, static_cast<int>(reasons_.size()) - 1))]++;
  if (last_seq_ >= 0 && s.trigger_seq > last_seq_ + 1) missing_ += s.trigger_seq - last_seq_ - 1;
  if (last_seq_ >= 0 && s.trigger_seq <= last_seq_) ++out_of_order_;
  last_seq_ = std::max(last_seq_, s.trigger_seq);
  const int32_t values[] = {s.capture_us, s.node_done_us, s.received_us, s.fused_us,
                            s.published_us};
  // Only frames that went through the pipeline have the whole breakdown.
  if (s.num_cameras_used == 0) return;
  for (size_t i = 0; i < kStages.size(); ++i)
    if (values[i] >= 0) stages_[i].add(values[i]);
}

std::string SkeletonStats::summary_json() const {
  using Json = nlohmann::ordered_json;
  const auto ms = [](double v) {
    return std::round(v * 1e4) / 1e4;
  };  // 0.1 us: the data's resolution
  Json reasons = Json::object();
  for (size_t i = 0; i < reasons_.size(); ++i)
    reasons[msg::reason_name(static_cast<int>(i))] = reasons_[i];
  Json latency = Json::object();
  for (size_t i = 0; i < kStages.size(); ++i) {
    const LatencySeries& l = stages_[i];
    latency[kStages[i]] = Json{{"p50", ms(l.percentile_ms(0.5))},
                               {"p99", ms(l.percentile_ms(0.99))},
                               {"max", ms(l.max_ms())},
                               {"n", l.count()}};
  }
  const Json o{
      {"skeletons", received_},        {"valid", valid_},    {"missing_sequences", missing_},
      {"out_of_order", out_of_order_}, {"reasons", reasons}, {"latency_ms", latency}};
  return o.dump();
}

void write_csv_header(std::ostream& out) {
  out << "trigger_seq,utime,valid,reason,num_cameras,cameras_mask,capture_us,node_done_us,received_"
         "us,fused_us,published_us";
  for (auto name : kJointNames) out << ',' << name << "_x," << name << "_y," << name << "_z";
  out << '\n';
}

void write_csv(std::ostream& out, const hullpose_msg::skeleton_t& s) {
  out << s.trigger_seq << ',' << s.utime << ',' << int{s.valid} << ',' << int{s.reason} << ','
      << s.num_cameras_used << ',' << s.cameras_used_mask << ',' << s.capture_us << ','
      << s.node_done_us << ',' << s.received_us << ',' << s.fused_us << ',' << s.published_us;
  for (int j = 0; j < kNumJoints; ++j)
    for (int k = 0; k < 3; ++k)
      out << ','
          << (j < s.num_joints ? s.position[static_cast<size_t>(j)][static_cast<size_t>(k)] : 0.f);
  out << '\n';
}

void write_jsonl(std::ostream& out, const hullpose_msg::skeleton_t& s) {
  using Json = nlohmann::ordered_json;
  Json joints = Json::object();
  for (int j = 0; j < s.num_joints; ++j) {
    const auto& p = s.position[static_cast<size_t>(j)];
    joints[j < kNumJoints ? kJointNames[static_cast<size_t>(j)] : "?"] = {p[0], p[1], p[2]};
  }
  const Json o{{"trigger_seq", s.trigger_seq},
               {"utime", s.utime},
               {"valid", s.valid},
               {"reason", s.reason},
               {"model_version", s.model_version},
               {"cameras", s.num_cameras_used},
               {"latency_us",
                {{"capture", s.capture_us},
                 {"node_done", s.node_done_us},
                 {"received", s.received_us},
                 {"fused", s.fused_us},
                 {"published", s.published_us}}},
               {"joints", joints}};
  out << o.dump() << '\n';
}

void write_estimate_header(std::ostream& out) {
  out << "frame,valid,reason,model";
  for (auto name : kJointNames) out << ',' << name << "_x," << name << "_y," << name << "_z";
  out << '\n';
}

void write_estimate(std::ostream& out, const hullpose_msg::skeleton_t& s, int64_t frame_offset) {
  out << s.trigger_seq - frame_offset << ',' << int{s.valid} << ',' << int{s.reason} << ','
      << s.model_version;
  for (int j = 0; j < kNumJoints; ++j)
    for (int k = 0; k < 3; ++k)
      out << ','
          << (j < s.num_joints ? s.position[static_cast<size_t>(j)][static_cast<size_t>(k)] : 0.f);
  out << '\n';
}

}  // namespace hullpose::listen
