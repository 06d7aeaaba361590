#pragma once
// The fusion host's live loop: SILHOUETTE and TRIGGER in (raw bytes, checked before decoding),
// frames assembled per trigger sequence, the pipeline run on each frame with enough views,
// SKELETON out for every closed frame (valid or with its reason) with the latency breakdown
// trigger -> capture -> node done -> received -> fused -> published, by default one frame late
// and smoothed with its neighbours (pose/lag_smoother.hpp), STATUS once a second, and,
// when asked, the coarse hull at a low rate on HULL (hull_publisher.hpp: its own thread, never
// in the frame loop's way).
// Single-threaded: one loop handles the bus and owns the assembler and the pipeline. The bus and
// the clock are the process's (service_main opens them); tests pass "memq://" and a SimClock.
#include <functional>
#include <hullpose_msg/node_status_t.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <memory>
#include <string>
#include <vector>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/clock.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/fusion_host/frame_assembler.hpp"
#include "hullpose/fusion_host/frame_pipeline.hpp"
#include "hullpose/fusion_host/hull_publisher.hpp"
#include "hullpose/pose/lag_smoother.hpp"

namespace hullpose::fusion {

struct ServiceConfig {
  AssemblerConfig assembler;
  int64_t status_period_us = 1'000'000;
  std::string silhouette_channel = "SILHOUETTE";
  std::string trigger_channel = "TRIGGER";
  std::string skeleton_channel = "SKELETON";
  std::string status_channel = "STATUS";
  HullPublishOptions hull;  // the optional HULL channel (--hull-rate HZ; off by default)
  // With lag.frames 1 (--lag-frames; default) a frame's SKELETON waits for the next frame to be
  // fused and is published smoothed with it; a frame held this long with no next one (the
  // triggers paused, a take ended) is published as fitted. Five frame periods of the slowest rig
  // we run (make demo's 10 Hz, where a wait of 100 ms would be a single period and a next frame
  // a little late would find its predecessor already gone out unsmoothed).
  pose::LagParams lag;
  int64_t lag_release_us = 500'000;
};

class FusionService {
 public:
  FusionService(bus::Bus& bus, Clock& clock, const Rig& rig, FramePipeline& pipeline,
                const ServiceConfig& config);
  ~FusionService();
  FusionService(const FusionService&) = delete;
  FusionService& operator=(const FusionService&) = delete;

  // Waits up to timeout_ms (at most 2 ms while frames are open, so that deadlines are checked)
  // for messages, handles what arrived, closes the frames that are due by the clock, publishes
  // STATUS when due.
  void step(int timeout_ms);
  // step() until keep_going() is false, then closes the open frames.
  void run(const std::function<bool()>& keep_going);
  void flush();

  const Counters& counters() const { return counters_; }
  const FrameAssembler& assembler() const { return assembler_; }
  int64_t skeletons_published() const { return published_; }

 private:
  void on_frame(const AssembledFrame& frame);
  // Publishes `s` with these joints (nullptr: its own) and its published latency grown by
  // `waited_us`.
  void publish_skeleton(hullpose_msg::skeleton_t& s, const JointPositions* joints,
                        int64_t waited_us);
  void release_held();
  void publish_status(int64_t now_us);

  bus::Bus& bus_;
  Clock& clock_;
  const Rig& rig_;
  FramePipeline& pipeline_;
  ServiceConfig config_;
  FrameAssembler assembler_;
  std::vector<bus::Subscription> subscriptions_;
  hullpose_msg::skeleton_t skeleton_;
  // The frame the lag holds (lag.frames 1), as it will be published but for its joints, since
  // held_since_us_ (monotonic); swapped with skeleton_, so neither allocates per frame.
  hullpose_msg::skeleton_t held_;
  int64_t held_since_us_ = 0;
  int64_t lag_seq_ = -2;  // the trigger sequence of the last frame given to lag_
  pose::LagSmoother lag_;
  JointPositions fitted_{};
  hullpose_msg::trigger_t trigger_;
  PoseEstimate estimate_;
  std::vector<uint8_t> buffer_, status_buffer_;
  Counters counters_;
  int64_t published_ = 0;
  int64_t last_seq_ = -1;
  // STATUS interval accounting
  int64_t next_status_us_ = 0;
  int64_t interval_frames_ = 0;
  int64_t interval_pipeline_us_ = 0;
  int64_t interval_start_us_ = 0;
  // Last: its worker uses counters_ and the bus until it is joined.
  std::unique_ptr<HullPublisher> hull_;  // set iff config.hull.rate_hz > 0
};

// Options of the pipeline on a fusion host's command line.
struct PipelineOptions {
  int resolution =
      128;  // --resolution N: voxels along the capture volume's longest axis (as --replay)
  int tolerance = 0;             // --tolerance K: a voxel may be missed by K present cameras
  std::string backend = "auto";  // --backend auto|cpu|cuda (fusion_host/gpu checks it)
  std::string pose = "track";    // --pose bottom-up|track (fusion_host/pose checks it)
  double smooth_hz = 0;          // --smooth-hz HZ: One Euro cut-off at rest (0: off; pose/one_euro)
};

// The command line of a fusion host process (--rig FILE, --lcm-url URL, --min-cameras N,
// --deadline-ms MS, --deadline-from first|trigger, --max-open N, --max-clock-skew-ms MS,
// --duration-s S, --ready-file FILE, --hull-rate HZ, and the PipelineOptions; --help prints the
// usage): builds the pipeline with `make_pipeline` and runs the service until SIGINT/SIGTERM or the
// duration. Returns the exit code; throws hullpose::Error on bad options or files (run it inside
// run_tool, common/tool.hpp).
int service_main(
    int argc, const char* const* argv, const char* tool,
    const std::function<std::unique_ptr<FramePipeline>(const Rig&, const PipelineOptions&)>&
        make_pipeline);

}  // namespace hullpose::fusion
