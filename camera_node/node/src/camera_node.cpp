#include "hullpose/camera_node/camera_node.hpp"

#include <unistd.h>

#include <algorithm>

#include "hullpose/camera_node/trigger_stage.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::camera_node {
namespace {

HULLPOSE_LOG_CATEGORY(Node, "camera_node")

constexpr int kLearnTimeoutMs = 5000;

std::string hostname() {
  char buf[256] = {};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

Rig load_rig_for(const NodeConfig& c) {
  try {
    return load_rig(c.rig_file);
  } catch (const Error& e) {
    HULLPOSE_THROW(c.file.string() << ": rig_file: " << e.what());
  }
}

}  // namespace

std::unique_ptr<bus::Bus> open_node_bus(const NodeConfig& config) {
  try {
    return bus::open_bus(config.lcm.url);
  } catch (const Error& e) {
    HULLPOSE_THROW(config.file.string() << ": lcm.url: " << e.what());
  }
}

CameraNode::CameraNode(NodeConfig config, bus::Bus& bus, const SourceRegistry& sources,
                       std::unique_ptr<FrameTrigger> trigger)
    : config_(std::move(config)),
      rig_(load_rig_for(config_)),
      cleanup_({config_.post.open_radius, config_.post.close_radius, config_.post.min_blob_area,
                config_.post.max_hole_area}) {
  const std::string file = config_.file.string();
  const CameraModel* cam = rig_.find(config_.camera_id);
  HULLPOSE_THROW_UNLESS(cam, file << ": camera_id: camera " << config_.camera_id
                                  << " is not in the rig file " << config_.rig_file.string());
  camera_ = *cam;
  const cv::Rect image(0, 0, camera_.width, camera_.height);
  roi_ = config_.post.roi.empty() ? image : config_.post.roi;
  HULLPOSE_THROW_UNLESS((roi_ & image) == roi_,
                        file << ": post.roi: [" << roi_.x << ", " << roi_.y << ", " << roi_.width
                             << ", " << roi_.height << "] is outside the " << camera_.width << "x"
                             << camera_.height << " image of camera " << camera_.id);
  const SourceContext context{config_.camera_id, camera_, rig_.volume, config_.base_dir};
  source_ = sources.create(config_.source.type, config_.source.params, context);
  if (!config_.bgs.background.empty()) {
    Params bg(file + ": bgs.background");
    bg.set("path", config_.bgs.background);
    background_source_ = SourceRegistry::builtin().create("file", bg, context);
  }
  try {
    subtractor_ = make_subtractor(config_.bgs.method, config_.bgs.params);
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.rfind(file, 0) == 0) throw;  // parameter errors name the file already
    HULLPOSE_THROW(file << ": " << what);
  }
  counters_.add("capture_timeout", 0);  // named up front, so counting never allocates per frame
  counters_.add("no_trigger", 0);
  counters_.add("corrupt_frame", 0);
  publisher_ = std::make_unique<SilhouettePublisher>(config_.lcm, bus, rig_.rig_id,
                                                     config_.camera_id, counters_);
  trigger_ = std::move(trigger);
  if (!trigger_ && config_.trigger.enabled) {
    trigger_ = std::make_unique<TriggerStage>(config_.trigger, bus, rig_.rig_id, config_.camera_id,
                                              source_->triggerable());
  }
  mask_ = cv::Mat::zeros(camera_.height, camera_.width, CV_8UC1);
  roi_mask_.create(roi_.size(), CV_8UC1);
}

CameraNode::~CameraNode() {
  try {
    stop();
  } catch (const std::exception& e) {
    HULLPOSE_LOG(Node, Error) << "camera " << config_.camera_id << ": while stopping: " << e.what();
  }
}

void CameraNode::start() {
  HULLPOSE_ASSERT(!started_);
  maybe_publish_status(true, hullpose_msg::node_status_t::STATE_STARTING, "starting");
  source_->start();
  started_ = true;
  HULLPOSE_LOG(Node, Info) << "camera " << config_.camera_id << ": " << source_->describe()
                           << ", method " << subtractor_->name();
  learn_background();
  if (trigger_)
    trigger_->start();  // after learning: a simulated master waits for every node's wire
  interval_start_us_ = monotonic_us();
}

void CameraNode::learn_background() {
  FrameSource& src = background_source_ ? *background_source_ : *source_;
  if (background_source_) background_source_->start();
  subtractor_->begin_learning(roi_.size());
  Frame frame;
  int learnt = 0;
  while (learnt < config_.bgs.learn_frames) {
    const GrabStatus s = src.grab(frame, kLearnTimeoutMs);
    if (s == GrabStatus::kEndOfStream) break;
    if (s == GrabStatus::kCorruptFrame) continue;  // logged by the source; learn from the others
    HULLPOSE_THROW_UNLESS(s == GrabStatus::kFrame,
                          "camera " << config_.camera_id << ": no frame within " << kLearnTimeoutMs
                                    << " ms while learning the background (" << src.describe()
                                    << ")");
    HULLPOSE_THROW_UNLESS(frame.image.cols == camera_.width && frame.image.rows == camera_.height,
                          "camera " << config_.camera_id << ": background frame is "
                                    << frame.image.cols << "x" << frame.image.rows
                                    << ", the rig says " << camera_.width << "x" << camera_.height);
    subtractor_->learn(frame.image(roi_));
    ++learnt;
  }
  HULLPOSE_THROW_UNLESS(learnt > 0, "camera " << config_.camera_id << ": no background frame from "
                                              << src.describe());
  if (learnt < config_.bgs.learn_frames) {
    HULLPOSE_LOG(Node, Warn) << "camera " << config_.camera_id
                             << ": learnt the background from only " << learnt << " of "
                             << config_.bgs.learn_frames << " frames";
  }
  subtractor_->end_learning();
  if (background_source_) background_source_->stop();
}

GrabStatus CameraNode::capture(Frame& frame, int timeout_ms) {
  const StageTimer timer;
  const GrabStatus s = source_->grab(frame, timeout_ms);
  last_capture_us_ = static_cast<int32_t>(timer.elapsed_us());
  if (s == GrabStatus::kTimeout) counters_.add("capture_timeout");
  if (s == GrabStatus::kCorruptFrame) counters_.add("corrupt_frame");
  return s;
}

const cv::Mat& CameraNode::process(const Frame& frame, const TriggerStamp& stamp) {
  HULLPOSE_THROW_UNLESS(frame.image.type() == CV_8UC3 && frame.image.cols == camera_.width &&
                            frame.image.rows == camera_.height,
                        "camera " << config_.camera_id << ": frame " << frame.sequence << " is "
                                  << frame.image.cols << "x" << frame.image.rows
                                  << ", the rig says " << camera_.width << "x" << camera_.height);
  StageTimer timer;
  subtractor_->apply(frame.image(roi_), roi_mask_);
  const int32_t subtract_us = static_cast<int32_t>(timer.elapsed_us());
  timer.restart();
  cleanup_.apply(roi_mask_);
  roi_mask_.copyTo(mask_(roi_));
  const int32_t morphology_us = static_cast<int32_t>(timer.elapsed_us());

  SilhouetteStamp s;
  s.trigger_seq = stamp.seq;
  s.trigger_utime = stamp.utime;
  s.capture_utime = frame.capture_utime - stamp.clock_offset_us;
  s.clock_offset_us = stamp.clock_offset_us;
  s.capture_us = last_capture_us_;
  s.subtract_us = subtract_us;
  s.morphology_us = morphology_us;
  int32_t encode_us = 0;
  publisher_->publish(mask_, s, &encode_us);

  ++frames_total_;
  ++interval_frames_;
  last_trigger_seq_ = stamp.seq;
  sum_capture_us_ += last_capture_us_;
  sum_subtract_us_ += subtract_us;
  sum_morphology_us_ += morphology_us;
  sum_encode_us_ += encode_us;
  maybe_publish_status(false, hullpose_msg::node_status_t::STATE_RUNNING, "running");
  return mask_;
}

void CameraNode::run(const std::atomic<bool>& stop_requested) {
  constexpr int kWaitMs = 200;  // how often the stop flag is looked at while nothing comes
  const bool exposes_on_trigger = trigger_ && source_->triggerable();
  if (trigger_ && config_.trigger.free_running) return run_free_running(stop_requested);
  Frame frame;
  while (!stop_requested.load(std::memory_order_relaxed)) {
    std::optional<TriggerStamp> stamp;
    if (exposes_on_trigger) {
      stamp = trigger_->next_instant(kWaitMs);
      if (!stamp) continue;
      source_->expose(stamp->seq, stamp->capture_utime);
    }
    const GrabStatus s = capture(frame, kWaitMs);
    if (s == GrabStatus::kEndOfStream) break;
    if (s == GrabStatus::kTimeout || s == GrabStatus::kCorruptFrame) continue;
    if (!trigger_) {
      stamp = TriggerStamp{frame.sequence, frame.capture_utime};
    } else if (!exposes_on_trigger) {
      stamp = trigger_->stamp(frame);
    }
    if (!stamp) {
      counters_.add("no_trigger");
      continue;
    }
    process(frame, *stamp);
    if (exposes_on_trigger) source_->prepare(stamp->seq + 1);  // the next trigger's, usually
  }
}

void CameraNode::run_free_running(const std::atomic<bool>& stop_requested) {
  constexpr int kWaitMs = 200;
  Frame frame;
  for (int64_t n = 0; !stop_requested.load(std::memory_order_relaxed);) {
    const GrabStatus s = capture(frame, kWaitMs);
    if (s == GrabStatus::kEndOfStream) break;
    if (s == GrabStatus::kTimeout || s == GrabStatus::kCorruptFrame) continue;
    // The source reuses its buffer at the next grab: keep a copy until the choice is made.
    Frame& kept = held_[static_cast<size_t>(n++) % kHeldFrames];
    frame.image.copyTo(kept.image);
    kept.sequence = frame.sequence;
    kept.capture_utime = frame.capture_utime;
    trigger_->offer(kept, decided_);
    for (const auto& [sequence, stamp] : decided_) {
      const auto it = std::find_if(held_.begin(), held_.end(), [&](const Frame& f) {
        return f.sequence == sequence && !f.image.empty();
      });
      if (it == held_.end()) {
        counters_.add("nearest_frame_gone");  // chosen after kHeldFrames newer frames came
        continue;
      }
      process(*it, stamp);
    }
  }
}

void CameraNode::stop() {
  if (!publisher_) return;
  if (started_) {
    source_->stop();
    started_ = false;
    publisher_->flush();  // the final STATUS counts every silhouette sent
    maybe_publish_status(true, hullpose_msg::node_status_t::STATE_STOPPED, "stopped");
    std::vector<std::pair<std::string, int64_t>> report = counters_.snapshot();
    if (trigger_) trigger_->report(report);
    std::string line;
    for (const auto& [name, value] : report) line += " " + name + "=" + std::to_string(value);
    HULLPOSE_LOG(Node, Info) << "camera " << config_.camera_id << ": stopped after "
                             << frames_total_ << " silhouettes;" << line;
  }
  publisher_->flush();
}

void CameraNode::maybe_publish_status(bool force, int8_t state, const std::string& message) {
  const int64_t now = monotonic_us();
  const int64_t elapsed = now - interval_start_us_;
  if (!force && elapsed < static_cast<int64_t>(config_.lcm.status_period_ms) * 1000) return;
  hullpose_msg::node_status_t st;
  st.utime = realtime_utime();
  st.rig_id = rig_.rig_id;
  st.role = "camera_node";
  st.node_id = config_.camera_id;
  st.hostname = hostname();
  st.state = state;
  st.message = message;
  st.fps = elapsed > 0 ? static_cast<float>(static_cast<double>(interval_frames_) * 1e6 /
                                            static_cast<double>(elapsed))
                       : 0.f;
  st.frames_total = frames_total_;
  st.last_trigger_seq = last_trigger_seq_;
  const double n = static_cast<double>(std::max<int64_t>(1, interval_frames_));
  const std::pair<const char*, int64_t> stages[] = {{"capture", sum_capture_us_},
                                                    {"subtract", sum_subtract_us_},
                                                    {"morphology", sum_morphology_us_},
                                                    {"encode", sum_encode_us_}};
  for (const auto& [name, sum] : stages) {
    st.stage_name.emplace_back(name);
    st.stage_ms.push_back(static_cast<float>(static_cast<double>(sum) / n / 1e3));
  }
  st.num_stages = static_cast<int32_t>(st.stage_name.size());
  auto counters = counters_.snapshot();
  counters.emplace_back("bytes_sent", publisher_->bytes_sent());
  counters.emplace_back("messages_sent", publisher_->messages_sent());
  if (trigger_) trigger_->report(counters);
  for (const auto& [name, value] : counters) {
    st.counter_name.push_back(name);
    st.counter_value.push_back(value);
  }
  st.num_counters = static_cast<int32_t>(st.counter_name.size());
  publisher_->publish_status(st);
  interval_start_us_ = now;
  interval_frames_ = 0;
  sum_capture_us_ = sum_subtract_us_ = sum_morphology_us_ = sum_encode_us_ = 0;
}

}  // namespace hullpose::camera_node
