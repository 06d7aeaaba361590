#pragma once
// The camera node's trigger stage (config trigger:): the trigger input (the GPIO line through
// libgpiod, or a simulated rig's wire) and the master's TRIGGER announcements in, each frame's
// trigger instant out, through camera_node/trigger's TriggerClient (sequence mapping robust to a
// late start, missed edges, lost announcements and clock offsets).
#include <memory>
#include <string>

#include "hullpose/camera_node/camera_node.hpp"
#include "hullpose/camera_node/trigger_client.hpp"

namespace hullpose::camera_node {

class TriggerStage final : public FrameTrigger {
 public:
  // Opens nothing. `simulated_sensor`: the source exposes one frame per edge (next_instant()),
  // else the camera exposes by itself and frames are stamped (stamp()).
  TriggerStage(const TriggerConfig& config, bus::Bus& bus, std::string rig_id, int camera_id,
               bool simulated_sensor);
  ~TriggerStage() override;

  void start() override;
  std::optional<TriggerStamp> stamp(const Frame& frame) override;
  std::optional<TriggerStamp> next_instant(int timeout_ms) override;
  void offer(const Frame& frame, std::vector<std::pair<int64_t, TriggerStamp>>& decided) override;
  void report(std::vector<std::pair<std::string, int64_t>>& out) const override;

 private:
  TriggerStamp to_stamp(const trigger::TaggedFrame& t, int64_t capture_utime) const;

  TriggerConfig config_;
  bus::Bus& bus_;
  int camera_id_;
  trigger::ListenerConfig listener_config_;
  trigger::NodeClock clock_;
  std::unique_ptr<trigger::EdgeSource> edges_;
  std::unique_ptr<trigger::TriggerClient> client_;
  std::vector<trigger::TaggedFrame> tagged_;
  // Free-running camera: how far the chosen frames were from their edges (sensor - edge).
  int64_t residual_count_ = 0, residual_abs_sum_us_ = 0, residual_abs_max_us_ = 0;
};

}  // namespace hullpose::camera_node
