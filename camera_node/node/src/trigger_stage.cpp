#include "hullpose/camera_node/trigger_stage.hpp"

#include <algorithm>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::camera_node {
namespace {
HULLPOSE_LOG_CATEGORY(Stage, "camera_node")
// A simulated sensor exposes at the edge: its frame is ready at once (no readout to wait for).
constexpr int64_t kSimulatedExposureDelayUs = 0;
}  // namespace

TriggerStage::TriggerStage(const TriggerConfig& config, bus::Bus& bus, std::string rig_id,
                           int camera_id, bool simulated_sensor)
    : config_(config),
      bus_(bus),
      camera_id_(camera_id),
      clock_{int64_t{config.clock_offset_ms} * 1000} {
  listener_config_.rig_id = std::move(rig_id);
  listener_config_.matcher.max_residual_us = config_.max_residual_us;
  listener_config_.expose_after_edge_us = simulated_sensor ? kSimulatedExposureDelayUs : -1;
}

TriggerStage::~TriggerStage() = default;

void TriggerStage::start() {
  try {
    edges_ = trigger::open_edge_source(config_.edges, clock_, config_.connect_timeout_ms);
  } catch (const Error& e) {
    HULLPOSE_THROW("camera " << camera_id_ << ": " << e.what());
  }
  client_ = std::make_unique<trigger::TriggerClient>(bus_, *edges_, listener_config_, clock_,
                                                     config_.channel);
  HULLPOSE_LOG(Stage, Info) << "camera " << camera_id_ << ": trigger input " << edges_->describe()
                            << ", "
                            << (listener_config_.expose_after_edge_us >= 0
                                    ? "simulated sensor exposes on each edge"
                                    : "camera exposes on the trigger line")
                            << ", announcements on " << config_.channel;
}

TriggerStamp TriggerStage::to_stamp(const trigger::TaggedFrame& t, int64_t capture_utime) const {
  // node realtime - master = (node realtime - node clock) + (node clock - master).
  const int64_t realtime_minus_node_clock = clock_.realtime_minus_node_us();
  return TriggerStamp{t.edge.seq, t.edge.utime, realtime_minus_node_clock + t.edge.offset_us,
                      capture_utime};
}

std::optional<TriggerStamp> TriggerStage::stamp(const Frame& frame) {
  HULLPOSE_ASSERT(client_);
  const std::optional<trigger::TaggedFrame> t =
      client_->tag(frame.sequence, frame.capture_utime, config_.wait_ms);
  if (!t) return std::nullopt;
  return to_stamp(*t, frame.capture_utime);
}

std::optional<TriggerStamp> TriggerStage::next_instant(int timeout_ms) {
  HULLPOSE_ASSERT(client_);
  const std::optional<trigger::TaggedFrame> t = client_->next_exposure(timeout_ms);
  if (!t) return std::nullopt;
  TriggerStamp s = to_stamp(*t, 0);
  s.capture_utime = t->frame_us + clock_.realtime_minus_node_us();
  return s;
}

void TriggerStage::offer(const Frame& frame,
                         std::vector<std::pair<int64_t, TriggerStamp>>& decided) {
  HULLPOSE_ASSERT(client_);
  client_->offer(frame.sequence, frame.capture_utime, tagged_);
  decided.clear();
  for (const trigger::TaggedFrame& t : tagged_) {
    decided.emplace_back(t.frame_id, to_stamp(t, 0));
    const int64_t r = t.residual_us < 0 ? -t.residual_us : t.residual_us;
    ++residual_count_;
    residual_abs_sum_us_ += r;
    residual_abs_max_us_ = std::max(residual_abs_max_us_, r);
  }
}

void TriggerStage::report(std::vector<std::pair<std::string, int64_t>>& out) const {
  if (!client_) return;
  const trigger::TriggerListener& l = client_->listener();
  out.emplace_back("trigger_synced", l.mapper().synced() ? 1 : 0);
  out.emplace_back("trigger_offset_us", l.mapper().offset_us());
  out.emplace_back("trigger_foreign", l.foreign_announcements());
  if (residual_count_ > 0) {
    out.emplace_back("trigger_residual_mean_us", residual_abs_sum_us_ / residual_count_);
    out.emplace_back("trigger_residual_max_us", residual_abs_max_us_);
  }
  for (const Counters* c : {&l.mapper().counters(), &l.matcher().counters(), &client_->counters()})
    for (const auto& [name, value] : c->snapshot()) out.emplace_back("trigger_" + name, value);
}

}  // namespace hullpose::camera_node
