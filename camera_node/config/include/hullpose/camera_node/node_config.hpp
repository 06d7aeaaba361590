#pragma once
// The configuration of one camera node, read from a YAML file (common/yaml.hpp) and
// validated at start: every error names the file and the field.
//
//   camera_id: 3
//   rig_file: rig.yaml              # relative paths are relative to this file's folder
//   source:                         # a frame-source backend (camera_node/source) and its
//                                   # parameters
//     type: libcamera               # libcamera | v4l2 | file | synthetic
//     exposure_us: 4000
//   bgs:
//     method: sobs                  # horprasert | codebook | sobs | mog2 | knn
//     learn_frames: 30              # empty-scene frames the background is learnt from
//     background: bg/rgb_%06d.png   # optional: learn from these files instead of the first frames
//     params: { epsilon_online: 0.008 }
//   post:
//     open_radius: 1                # morphological opening (pixels; 0 = off)
//     close_radius: 0               # closing (off: it joins limbs in the hull, mask_cleanup.hpp)
//     min_blob_area: 32             # connected components smaller than this are removed
//     max_hole_area: 64             # enclosed background regions up to this size are filled
//     roi: [0, 0, 640, 480]         # x y w h; pixels outside are background (default: all)
//   lcm:
//     url: udpm://239.255.76.67:7667?ttl=1
//     rig_key: /etc/hullpose/rig.key  # the rig's key: messages authenticated (docs/messages.md)
//     queue_depth: 4                # silhouettes waiting for the network; more: dropped, counted
//     status_period_ms: 1000
//   trigger:                        # optional: without it the node is free-running (trigger_seq =
//                                   # the frame counter, unsynchronised with the other nodes)
//     edges: gpiod                  # the trigger input: gpiod (the trigger GPIO; production) |
//                                   # wire (hullpose-trigger-master --line wire:PATH;
//                                   # simulated rigs)
//     chip: gpiochip0               # gpiod: the chip (name, path or label) ...
//     line: 17                      # ... and the input line's offset
//     path: /run/hullpose/wire.sock # wire: the master's socket
//     channel: TRIGGER              # the master's announcements (sequence, utime)
//     max_residual_us: 5000         # how far a frame's exposure may be from its edge
//     wait_ms: 50                   # how long a frame waits for its edge's announcement
//     connect_timeout_ms: 10000     # wire: how long start() waits for the master's socket
//     clock_offset_ms: 0            # tests: a board whose clock is this far off (0 in production)
//     clock_step_ms: 0              # tests: the board clock steps by this much (an NTP step) ...
//     clock_step_after: 0           # ... once this many frames have been stamped
// With a trigger, a camera that exposes on the trigger line (libcamera/v4l2 with external trigger)
// gets each frame tagged with its edge; a simulated sensor (file, synthetic) exposes exactly one
// frame per edge, showing the instant of that trigger.
#include <filesystem>
#include <opencv2/core/types.hpp>
#include <string>

#include "hullpose/camera_node/params.hpp"

namespace hullpose::camera_node {

struct SourceConfig {
  std::string type;
  Params params;  // every key of `source:` except `type`
};

struct BgsConfig {
  std::string method;
  int learn_frames = 30;
  std::string
      background;  // optional image pattern (printf %d) or video, resolved to an absolute path
  Params params;
};

struct PostConfig {
  int open_radius = 1;
  int close_radius = 0;
  int min_blob_area = 32;
  int max_hole_area = 64;
  cv::Rect roi;  // empty: the whole image
};

struct LcmConfig {
  std::string url = "udpm://239.255.76.67:7667?ttl=1";
  std::filesystem::path rig_key;  // empty: an open rig (no authentication)
  std::string silhouette_channel = "SILHOUETTE";
  std::string status_channel = "STATUS";
  int queue_depth = 4;
  int status_period_ms = 1000;
};

struct TriggerConfig {
  bool enabled = false;  // a trigger: section is present
  std::string edges;     // the edge source: "gpiod:CHIP:LINE" or "wire:PATH"
  std::string channel = "TRIGGER";
  // trigger.camera: "triggered" (the sensor exposes on the trigger line; default) or
  // "free_running" (no trigger input on the sensor: the frame nearest each edge is published,
  // set max_residual_us to half the frame interval).
  bool free_running = false;
  int max_residual_us = 5000;
  int wait_ms = 50;
  int connect_timeout_ms = 10000;
  int clock_offset_ms = 0;
  int clock_step_ms = 0;
  int clock_step_after = 0;
};

struct NodeConfig {
  std::filesystem::path file;      // where it was read from (for messages)
  std::filesystem::path base_dir;  // relative paths in the file are relative to this
  int camera_id = -1;
  std::filesystem::path rig_file;  // absolute
  SourceConfig source;
  BgsConfig bgs;
  PostConfig post;
  LcmConfig lcm;
  TriggerConfig trigger;
};

// Reads and checks the file's structure and scalar ranges; throws hullpose::Error naming the file
// and the field. Stage parameters are checked when the stages are built (CameraNode's constructor),
// so that the whole configuration is validated before any device is opened.
NodeConfig load_node_config(const std::filesystem::path& file);
// The same from the file's text: `file` names it in errors and is the base of relative paths;
// it is not read (a rig_key it names is). Used by fuzz_node_config.
NodeConfig parse_node_config(const std::string& text, const std::filesystem::path& file);

}  // namespace hullpose::camera_node
