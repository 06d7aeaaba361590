#include "hullpose/fusion_host/fusion_service.hpp"

#include <unistd.h>

#include <algorithm>
#include <climits>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/msg/wire.hpp"

namespace hullpose::fusion {
HULLPOSE_LOG_CATEGORY(Service, "fusion_service")

namespace {
int32_t us_after(int64_t t, int64_t utime) {
  if (t <= 0) return -1;  // unknown
  return static_cast<int32_t>(std::clamp<int64_t>(t - utime, INT32_MIN, INT32_MAX));
}
}  // namespace

FusionService::FusionService(bus::Bus& bus, Clock& clock, const Rig& rig, FramePipeline& pipeline,
                             const ServiceConfig& config)
    : bus_(bus),
      clock_(clock),
      rig_(rig),
      pipeline_(pipeline),
      config_(config),
      assembler_(rig, config.assembler, [this](const AssembledFrame& f) { on_frame(f); }),
      lag_(config.lag) {
  skeleton_.rig_id = rig.rig_id;
  skeleton_.subject_id = 0;
  skeleton_.num_joints = kNumJoints;
  skeleton_.joint_name.assign(kJointNames.begin(), kJointNames.end());
  skeleton_.position.assign(kNumJoints, std::vector<float>(3, 0.f));
  skeleton_.confidence.assign(kNumJoints, 0.f);
  skeleton_.model_version = 0;
  held_ = skeleton_;
  buffer_.resize(static_cast<size_t>(skeleton_.getEncodedSize()) +
                 1024);         // no allocation per frame
  constexpr int kQueue = 1000;  // a burst of a whole rig's silhouettes while a frame is fused
  subscriptions_.push_back(bus_.subscribe(
      config_.silhouette_channel,
      [this](std::span<const uint8_t> bytes, const std::string&) {
        assembler_.on_bytes(bytes, clock_.realtime_utime(), clock_.monotonic_us());
      },
      kQueue));
  subscriptions_.push_back(wire::subscribe(
      bus_, config_.trigger_channel, trigger_, counters_, "malformed_trigger",
      [this](const hullpose_msg::trigger_t& t) { assembler_.on_trigger(t, clock_.monotonic_us()); },
      kQueue));
  if (config_.hull.rate_hz > 0)
    hull_ = std::make_unique<HullPublisher>(bus_, rig.rig_id, config_.hull, counters_);
  interval_start_us_ = clock_.monotonic_us();
  next_status_us_ = interval_start_us_;
}

FusionService::~FusionService() = default;

void FusionService::on_frame(const AssembledFrame& f) {
  if (last_seq_ >= 0 && f.trigger_seq > last_seq_ + 1) {
    // Sequences that neither a silhouette nor an announcement reached: still accounted for.
    counters_.add("unseen_sequences", f.trigger_seq - last_seq_ - 1);
  }
  last_seq_ = f.trigger_seq;
  skeleton_.utime = f.utime;
  skeleton_.trigger_seq = f.trigger_seq;
  skeleton_.cameras_used_mask = static_cast<int64_t>(f.camera_mask);
  skeleton_.num_cameras_used = static_cast<int32_t>(f.views.size());
  int64_t capture = 0, node_done = 0;
  for (const View& v : f.views) {
    capture = std::max(capture, v.capture_utime);
    node_done = std::max(node_done, v.node_done_utime);
  }
  estimate_ = PoseEstimate{};
  // Latencies: this host's realtime when the frame was taken up, plus measured durations, so that
  // received <= fused <= published holds on any clock.
  const int64_t start_utime = clock_.realtime_utime();
  const StageTimer t;
  if (f.status == FrameStatus::kTooFew) {
    estimate_.reason = hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS;
    counters_.add("skeleton_too_few_cameras");
  } else {
    try {
      pipeline_.process(f, estimate_);
    } catch (const std::exception& e) {
      // A pipeline must not throw (FramePipeline); if one does (a bug, the system), this frame
      // is published as failed and the service goes on with the next.
      HULLPOSE_LOG(Service, Error)
          << "frame " << f.trigger_seq << ": pipeline failed: " << e.what();
      counters_.add("pipeline_error");
      estimate_ = PoseEstimate{};
      estimate_.reason = hullpose_msg::skeleton_t::REASON_FIT_FAILED;
    }
    interval_pipeline_us_ += t.elapsed_us();
    ++interval_frames_;
    counters_.add(estimate_.valid ? "skeleton_valid" : "skeleton_invalid");
  }
  skeleton_.valid = estimate_.valid;
  skeleton_.reason = estimate_.reason;
  skeleton_.model_version = estimate_.model_version;
  for (int j = 0; j < kNumJoints; ++j) {
    const auto ju = static_cast<size_t>(j);
    std::copy(estimate_.position_mm[ju].begin(), estimate_.position_mm[ju].end(),
              skeleton_.position[ju].begin());
    skeleton_.confidence[ju] = estimate_.confidence[ju];
  }
  skeleton_.capture_us = us_after(capture, f.utime);
  skeleton_.node_done_us = us_after(node_done, f.utime);
  skeleton_.received_us = us_after(f.last_received_utime, f.utime);
  const int64_t received = std::max(start_utime, f.last_received_utime);
  skeleton_.fused_us =
      estimate_.fused_after_us < 0 ? -1 : us_after(received + estimate_.fused_after_us, f.utime);
  skeleton_.published_us = us_after(received + t.elapsed_us(), f.utime);
  if (config_.lag.frames == 0) {
    publish_skeleton(skeleton_, nullptr, 0);
  } else {
    for (size_t j = 0; j < fitted_.size(); ++j) {
      const auto& p = estimate_.position_mm[j];
      fitted_[j] = {p[0], p[1], p[2]};
    }
    const int64_t now = clock_.monotonic_us();
    if (const JointPositions* joints =
            lag_.push(fitted_, skeleton_.valid, lag_seq_ + 1 == f.trigger_seq))
      publish_skeleton(held_, joints, now - held_since_us_);
    std::swap(held_, skeleton_);
    held_since_us_ = now;
    lag_seq_ = f.trigger_seq;
  }
  // After the skeleton: the view's hull never delays the pose.
  if (hull_ && estimate_.hull && estimate_.hull_grid)
    hull_->offer(*estimate_.hull, *estimate_.hull_grid, f.utime, f.trigger_seq);
}

void FusionService::step(int timeout_ms) {
  // Deadlines are checked at least every 2 ms while frames are open.
  const int wait_ms = assembler_.open_frames() > 0 ? std::min(timeout_ms, 2) : timeout_ms;
  // What is pending, but not unboundedly: a flood must not keep the deadlines from being checked.
  constexpr int kMaxPerStep = 256;
  if (bus_.handle(wait_ms))
    for (int i = 1; i < kMaxPerStep && bus_.handle(0); ++i) {
    }
  const int64_t now = clock_.monotonic_us();
  assembler_.poll(now);
  if (lag_.holding() && now - held_since_us_ >= config_.lag_release_us) release_held();
  if (now >= next_status_us_) publish_status(now);
}

void FusionService::publish_skeleton(hullpose_msg::skeleton_t& s, const JointPositions* joints,
                                     int64_t waited_us) {
  if (joints != nullptr && s.valid)
    for (size_t j = 0; j < joints->size(); ++j)
      for (int a = 0; a < 3; ++a)
        s.position[j][static_cast<size_t>(a)] = static_cast<float>((*joints)[j][a]);
  if (s.published_us != -1)  // -1: unknown (us_after)
    s.published_us = static_cast<int32_t>(std::min<int64_t>(s.published_us + waited_us, INT32_MAX));
  if (!wire::publish(bus_, config_.skeleton_channel, s, buffer_)) counters_.add("publish_error");
  ++published_;
}

void FusionService::release_held() {
  const JointPositions* joints = lag_.release();
  if (joints != nullptr) publish_skeleton(held_, joints, clock_.monotonic_us() - held_since_us_);
}

void FusionService::run(const std::function<bool()>& keep_going) {
  while (keep_going()) step(50);
  flush();
}

void FusionService::flush() {
  assembler_.flush();
  release_held();
  if (hull_) hull_->drain();
  publish_status(clock_.monotonic_us());
}

void FusionService::publish_status(int64_t now_us) {
  hullpose_msg::node_status_t s{};
  s.utime = clock_.realtime_utime();
  s.rig_id = rig_.rig_id;
  s.role = "fusion_host";
  s.node_id = -1;
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  s.hostname = host;
  const auto& c = assembler_.counters();
  const int64_t partial = c.get("fused_partial");
  const bool degraded = c.get("too_few_cameras") + c.get("no_views") > 0 || partial > 0;
  s.state = degraded ? hullpose_msg::node_status_t::STATE_DEGRADED
                     : hullpose_msg::node_status_t::STATE_RUNNING;
  s.message =
      degraded ? "some frames fused from fewer cameras or dropped; see counters" : "all cameras";
  const double seconds =
      std::max<double>(1e-3, static_cast<double>(now_us - interval_start_us_) / 1e6);
  s.fps = static_cast<float>(static_cast<double>(interval_frames_) / seconds);
  s.frames_total = published_;
  s.last_trigger_seq = last_seq_;
  s.stage_name = {"pipeline"};
  s.stage_ms = {interval_frames_
                    ? static_cast<float>(static_cast<double>(interval_pipeline_us_) / 1000.0 /
                                         static_cast<double>(interval_frames_))
                    : 0.f};
  s.num_stages = 1;
  for (const Counters* counters : {&c, static_cast<const Counters*>(&counters_)}) {
    for (const auto& [name, value] : counters->snapshot()) {
      s.counter_name.push_back(name);
      s.counter_value.push_back(value);
    }
  }
  for (const auto& [name, value] : bus_.drops()) {
    s.counter_name.push_back(name);
    s.counter_value.push_back(value);
  }
  s.num_counters = static_cast<int32_t>(s.counter_name.size());
  if (!wire::publish(bus_, config_.status_channel, s, status_buffer_))
    counters_.add("publish_error");
  interval_frames_ = 0;
  interval_pipeline_us_ = 0;
  interval_start_us_ = now_us;
  next_status_us_ = now_us + config_.status_period_us;
}

}  // namespace hullpose::fusion
