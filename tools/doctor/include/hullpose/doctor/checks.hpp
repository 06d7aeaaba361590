#pragma once
// The start-up checks of hullpose-doctor: what silently breaks LCM and the trigger on a board —
// a receive buffer too small for the message rate, no multicast route, multicast TTL 0 on a real
// LAN, the trigger GPIO chip or line missing or busy, the camera absent, the clock not
// synchronised, a missing or unreadable rig file or rig key. Each result says what to run to fix
// it.
//
//   Host host("/");                                  // or a fake root (tests)
//   Setup setup = setup_from_etc(host, Role::kAll);  // /etc/hullpose/hullpose.conf, camera*.yaml
//   for (const Result& r : run_checks(host, setup)) ...
#include <optional>
#include <string>
#include <vector>

#include "hullpose/doctor/host.hpp"

namespace hullpose::doctor {

// kConsumer: a LAN host that reads the skeletons (hullpose-web): network, clock, rig file, key.
enum class Role { kAll, kCameraNode, kTriggerMaster, kFusionHost, kConsumer };
// all | camera-node | trigger-master | fusion-host | consumer
Role parse_role(const std::string& text);

enum class Status { kOk, kWarn, kFail, kSkip };
const char* status_name(Status s);

struct Result {
  std::string check;  // e.g. net.multicast_route
  Status status = Status::kOk;
  std::string message;
  std::string fix;  // what to run (empty when ok)
};

// One camera node's view of its config file (camera_node/config), as far as the checks need it.
struct CameraSetup {
  std::string config_file;  // as given (shown in messages)
  std::string error;        // the config did not load: why
  int camera_id = -1;
  std::string rig_file;  // absolute, on the checked machine
  std::string source;    // libcamera | v4l2 | file | synthetic
  std::string device;    // v4l2: the device path; libcamera: the camera id (may be empty)
  bool external_trigger = false;
  std::string trigger_edges;  // "gpiod:CHIP:LINE", "wire:PATH" or empty
  std::string lcm_url;
  std::string rig_key;  // lcm.rig_key, absolute on the checked machine; empty: an open rig
};

struct Setup {
  Role role = Role::kAll;
  std::string lcm_url;       // empty: LCM's default (udpm://239.255.76.67:7667?ttl=0)
  std::string rig_file;      // fusion host / all; absolute on the checked machine; may be empty
  std::string trigger_line;  // trigger master: gpiod:CHIP:OFFSET | wire:PATH | sim; may be empty
  std::string rig_id;        // what the trigger master announces (HULLPOSE_RIG_ID); may be empty
  std::string rig_key;       // the rig's key file (HULLPOSE_RIG_KEY); empty: an open rig
  std::vector<CameraSetup> cameras;
};

// Reads /etc/hullpose/*.conf (the units' environment files, KEY=VALUE: HULLPOSE_LCM_URL,
// HULLPOSE_RIG, HULLPOSE_RIG_ID, HULLPOSE_RIG_KEY, HULLPOSE_TRIGGER_LINE) and, for camera nodes,
// every /etc/hullpose/camera*.yaml under the root.
Setup setup_from_etc(const Host& host, Role role);
// A camera node's config file (a path on the checked machine, read under the root).
CameraSetup load_camera(const Host& host, const std::string& config_file);

std::vector<Result> run_checks(const Host& host, const Setup& setup);

// The parts of an LCM URL the network checks need; nullopt for non-udpm URLs (memq://, file://).
struct UdpmUrl {
  std::string group = "239.255.76.67";
  int port = 7667;
  int ttl = 0;                  // LCM's default
  long long recv_buf_size = 0;  // 0: LCM leaves SO_RCVBUF at net.core.rmem_default
};
std::optional<UdpmUrl> parse_udpm(const std::string& url);

}  // namespace hullpose::doctor
