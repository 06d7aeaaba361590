#include "hullpose/doctor/checks.hpp"

#include <arpa/inet.h>
#include <net/if.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <sstream>

#include "hullpose/auth/rig_key.hpp"
#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::doctor {
namespace fs = std::filesystem;

Role parse_role(const std::string& text) {
  if (text == "all") return Role::kAll;
  if (text == "camera-node") return Role::kCameraNode;
  if (text == "trigger-master") return Role::kTriggerMaster;
  if (text == "fusion-host") return Role::kFusionHost;
  if (text == "consumer") return Role::kConsumer;
  HULLPOSE_THROW("--role must be all, camera-node, trigger-master, fusion-host or consumer, got '"
                 << text << "'");
}

const char* status_name(Status s) {
  switch (s) {
    case Status::kOk:
      return "ok";
    case Status::kWarn:
      return "warn";
    case Status::kFail:
      return "FAIL";
    case Status::kSkip:
      return "skip";
  }
  return "?";
}

std::optional<UdpmUrl> parse_udpm(const std::string& url) {
  UdpmUrl u;
  if (url.empty()) return u;
  const std::string scheme = "udpm://";
  if (url.rfind(scheme, 0) != 0) return std::nullopt;
  const std::string rest = url.substr(scheme.size());
  const size_t q = rest.find('?');
  const std::string address = rest.substr(0, q);
  const size_t colon = address.find(':');
  u.group = address.substr(0, colon);
  if (colon != std::string::npos) u.port = std::atoi(address.c_str() + colon + 1);
  if (q != std::string::npos) {
    std::istringstream opts(rest.substr(q + 1));
    for (std::string kv; std::getline(opts, kv, '&');) {
      const size_t eq = kv.find('=');
      if (eq == std::string::npos) continue;
      const std::string key = kv.substr(0, eq), value = kv.substr(eq + 1);
      if (key == "ttl") u.ttl = std::atoi(value.c_str());
      if (key == "recv_buf_size") u.recv_buf_size = std::atoll(value.c_str());
    }
  }
  return u;
}

namespace {

std::string trim(std::string s) {
  const auto space = [](unsigned char c) { return std::isspace(c) != 0; };
  s.erase(s.begin(), std::find_if_not(s.begin(), s.end(), space));
  s.erase(std::find_if_not(s.rbegin(), s.rend(), space).base(), s.end());
  return s;
}

std::optional<long long> read_number(const Host& host, const std::string& path) {
  const auto text = host.read(path);
  if (!text) return std::nullopt;
  const std::string t = trim(*text);
  if (t.empty() || t.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  return std::stoll(t);
}

Result ok(std::string check, std::string message) {
  return {std::move(check), Status::kOk, std::move(message), {}};
}
Result skip(std::string check, std::string message) {
  return {std::move(check), Status::kSkip, std::move(message), {}};
}
Result bad(Status s, std::string check, std::string message, std::string fix) {
  return {std::move(check), s, std::move(message), std::move(fix)};
}

// --- the network: what LCM over UDP multicast needs ---------------------------------------------

struct Route {
  bool found = false;
  std::string iface;
};

// The main table's most specific route to `group` (/proc/net/route: hexadecimal words in the
// kernel's byte order, compared in that order). Policy routing rules are not followed.
Route route_to(const Host& host, const std::string& group) {
  Route best;
  in_addr addr{};
  if (inet_pton(AF_INET, group.c_str(), &addr) != 1) return best;
  const auto table = host.read("/proc/net/route");
  if (!table) return best;
  std::istringstream lines(*table);
  std::string line;
  std::getline(lines, line);  // header
  int best_len = -1;
  while (std::getline(lines, line)) {
    std::istringstream f(line);
    std::string iface, dest, gateway, flags, refcnt, use, metric, mask;
    if (!(f >> iface >> dest >> gateway >> flags >> refcnt >> use >> metric >> mask)) continue;
    const uint32_t d = static_cast<uint32_t>(std::stoul(dest, nullptr, 16));
    const uint32_t m = static_cast<uint32_t>(std::stoul(mask, nullptr, 16));
    if ((std::stoul(flags, nullptr, 16) & 0x1) == 0) continue;  // RTF_UP
    if ((addr.s_addr & m) != d) continue;
    const int len = std::popcount(m);
    if (len > best_len) {
      best_len = len;
      best = {true, iface};
    }
  }
  return best;
}

void check_network(const Host& host, const Setup& setup, std::vector<Result>& out) {
  const std::string url =
      setup.lcm_url.empty() ? "udpm://239.255.76.67:7667 (LCM's default)" : setup.lcm_url;
  const auto udpm = parse_udpm(setup.lcm_url);
  if (!udpm) {
    out.push_back(skip("net", "LCM URL " + url + " is not UDP multicast; no network checks"));
    return;
  }
  // Multicast route: without one, every publish fails with "Network is unreachable".
  const Route route = route_to(host, udpm->group);
  if (!route.found) {
    out.push_back(bad(
        Status::kFail, "net.multicast_route",
        "no route to the LCM group " + udpm->group + " (LCM URL " + url +
            "): every publish fails with 'Network is unreachable' and nothing is received",
        "ip route add 224.0.0.0/4 dev <rig interface>   (persist it in /etc/network/interfaces or "
        "NetworkManager: nmcli connection modify <conn> +ipv4.routes 224.0.0.0/4)"));
  } else {
    const std::optional<unsigned> flags_known = host.interface_flags(route.iface);
    const unsigned flags = flags_known.value_or(0);
    if (flags_known && ((flags & IFF_UP) == 0 || (flags & IFF_MULTICAST) == 0)) {
      out.push_back(bad(Status::kFail, "net.multicast_route",
                        "the route to " + udpm->group + " goes through " + route.iface +
                            ", which is " + ((flags & 0x1) == 0 ? "down" : "not multicast-capable"),
                        "ip link set " + route.iface + " up multicast on"));
    } else {
      out.push_back(ok("net.multicast_route", udpm->group + " routes through " + route.iface));
    }
  }
  // TTL 0 keeps every packet on this host: fine for a one-machine demo, silent death on a LAN.
  if (route.found && route.iface != "lo" && udpm->ttl == 0) {
    out.push_back(bad(
        Status::kFail, "net.multicast_ttl",
        "LCM URL " + url +
            " has ttl=0 (LCM's default): packets never leave this host, but the "
            "group routes through " +
            route.iface + " to the rest of the rig",
        "set ?ttl=1 in HULLPOSE_LCM_URL (/etc/hullpose/hullpose.conf) and in lcm.url of "
        "/etc/hullpose/camera*.yaml, e.g. udpm://239.255.76.67:7667?ttl=1&recv_buf_size=4194304"));
  } else {
    out.push_back(ok("net.multicast_ttl",
                     "ttl=" + std::to_string(udpm->ttl) +
                         (udpm->ttl == 0 ? " (this host only, the route is loopback)" : "")));
  }
  // Receive buffer: all cameras send one silhouette each right after a trigger edge, so the fusion
  // host takes a burst of cameras x silhouette bytes; it must hold a few such bursts while a frame
  // is carved. LCM sets SO_RCVBUF only when the URL has recv_buf_size (then the kernel caps it at
  // rmem_max and doubles it for its bookkeeping); otherwise the socket gets rmem_default.
  const auto rmem_max = read_number(host, "/proc/sys/net/core/rmem_max");
  const auto rmem_default = read_number(host, "/proc/sys/net/core/rmem_default");
  if (!rmem_max || !rmem_default) {
    out.push_back(skip("net.rmem", "/proc/sys/net/core/rmem_max or rmem_default unreadable"));
    return;
  }
  constexpr long long kSilhouetteBytes =
      32 * 1024;                      // an 800x600 RLE silhouette with margin (typ. 2-8 KiB)
  constexpr long long kBursts = 4;    // trigger periods the host may fall behind
  constexpr long long kTruesize = 2;  // kernel bookkeeping per datagram
  long long cameras = 0;
  if (setup.role == Role::kFusionHost || setup.role == Role::kAll) {
    if (!setup.rig_file.empty()) {
      try {
        cameras = static_cast<long long>(load_rig(host.at(setup.rig_file)).cameras.size());
      } catch (const Error&) {
        cameras = 8;  // rig.file reports the error; assume the thesis rig
      }
    } else {
      cameras = 8;
    }
  }
  const long long need =
      std::max<long long>(256 * 1024, cameras * kSilhouetteBytes * kBursts * kTruesize);
  const long long have =
      udpm->recv_buf_size > 0 ? 2 * std::min(udpm->recv_buf_size, *rmem_max) : *rmem_default;
  const std::string why =
      cameras > 0
          ? std::to_string(cameras) + " cameras x " + std::to_string(kSilhouetteBytes / 1024) +
                " KiB x " + std::to_string(kBursts) + " trigger periods x 2 (kernel overhead)"
          : std::string("TRIGGER and STATUS messages");
  if (have < need) {
    const std::string source = udpm->recv_buf_size > 0
                                   ? "recv_buf_size=" + std::to_string(udpm->recv_buf_size) +
                                         " capped by net.core.rmem_max=" + std::to_string(*rmem_max)
                                   : "no recv_buf_size in the URL, so net.core.rmem_default=" +
                                         std::to_string(*rmem_default);
    // The kernel doubles what LCM asks for: ask for half the need, allow at least what the URL
    // asks.
    const long long ask =
        static_cast<long long>(std::bit_ceil(static_cast<unsigned long long>(need / 2)));
    const long long max = std::max(ask, udpm->recv_buf_size);
    std::string fix = "sysctl -w net.core.rmem_max=" + std::to_string(max) +
                      "   (persist: /usr/lib/sysctl.d/60-hullpose.conf from hullpose-common, or a "
                      "file in /etc/sysctl.d/)";
    if (udpm->recv_buf_size < ask)
      fix += " and add &recv_buf_size=" + std::to_string(ask) + " to the LCM URL";
    out.push_back(bad(Status::kFail, "net.rmem",
                      "LCM's receive buffer is " + std::to_string(have) + " bytes (" + source +
                          "), needs " + std::to_string(need) + " (" + why +
                          "): bursts of silhouettes are dropped by the kernel, silently",
                      fix));
  } else {
    out.push_back(ok("net.rmem", "receive buffer " + std::to_string(have) +
                                     " bytes >= " + std::to_string(need) + " (" + why + ")"));
  }
}

// --- the clock
// ------------------------------------------------------------------------------------

void check_clock(const Host& host, std::vector<Result>& out) {
  const std::vector<std::string> procs = host.processes();
  const auto running = [&](const char* name) {
    return std::find(procs.begin(), procs.end(), name) != procs.end();
  };
  std::string daemons;
  for (const char* d : {"chronyd", "ntpd", "systemd-timesyn", "ptp4l", "phc2sys", "timemaster"})
    if (running(d)) daemons += (daemons.empty() ? "" : ", ") + std::string(d);
  const ClockState clock = host.clock();
  if (daemons.empty()) {
    out.push_back(
        bad(Status::kWarn, "clock.sync",
            "no time synchronisation daemon runs (chronyd, ntpd, systemd-timesyncd, ptp4l + "
            "phc2sys): board "
            "clocks drift apart, so latencies are wrong and the fusion host's --max-clock-skew-ms "
            "drops frames",
            "apt install chrony (point every board at the fusion host: 'server <host> iburst' in "
            "/etc/chrony/chrony.conf) or, with PTP-capable NICs, apt install linuxptp"));
    return;
  }
  if (running("ptp4l") && !running("phc2sys") && !running("timemaster")) {
    out.push_back(bad(
        Status::kWarn, "clock.sync",
        "ptp4l runs but phc2sys does not: the NIC's clock follows PTP, the system clock does not",
        "phc2sys -s <interface> -w   (or systemctl enable --now phc2sys@<interface>)"));
    return;
  }
  if (!clock.error.empty()) {
    out.push_back(skip("clock.sync", daemons + " running; " + clock.error));
    return;
  }
  if (!clock.synchronised) {
    out.push_back(
        bad(Status::kWarn, "clock.sync",
            daemons + " running, but the kernel clock is not synchronised (STA_UNSYNC; max error " +
                std::to_string(clock.max_error_us) + " us)",
            running("chronyd")
                ? "chronyc tracking; chronyc sources -v   (is the server reachable? "
                  "'chronyc makestep' after a large offset)"
                : "timedatectl timesync-status; or pmc -u -b 0 'GET TIME_STATUS_NP' for PTP"));
    return;
  }
  out.push_back(ok("clock.sync", daemons + " running, clock synchronised (max error " +
                                     std::to_string(clock.max_error_us) + " us)"));
}

// --- the trigger GPIO
// -----------------------------------------------------------------------------

void check_gpio(const Host& host, const std::string& who, const std::string& spec,
                const std::string& own_consumer, std::vector<Result>& out) {
  const std::string check = "gpio." + who;
  // spec: gpiod:CHIP:OFFSET
  const size_t last = spec.rfind(':');
  const std::string chip =
      spec.substr(6, last == std::string::npos || last < 6 ? std::string::npos : last - 6);
  const std::string offset_text = last == std::string::npos ? "" : spec.substr(last + 1);
  if (spec.rfind("gpiod:", 0) != 0 || last == std::string::npos || last < 6 ||
      offset_text.empty() || offset_text.find_first_not_of("0123456789") != std::string::npos) {
    out.push_back(bad(Status::kFail, check, "trigger line '" + spec + "' is not gpiod:CHIP:OFFSET",
                      "e.g. gpiod:gpiochip0:17 (gpioinfo lists the chips and lines)"));
    return;
  }
  const unsigned offset = static_cast<unsigned>(std::stoul(offset_text));
  const GpioChip c = host.gpio_chip(chip);
  if (!c.found) {
    std::string present;
    for (const auto& p : c.present) present += (present.empty() ? "" : ", ") + p;
    out.push_back(bad(
        Status::kFail, check,
        "GPIO chip '" + chip + "' of " + spec + " not found: " + c.error +
            " (chips here: " + (present.empty() ? "none" : present) + ")",
        "gpiodetect lists the chips (on a Raspberry Pi 5 the header is 'pinctrl-rp1'); fix the "
        "chip in the "
        "config, or use wire:PATH / a free-running camera on a machine without the trigger GPIO"));
    return;
  }
  if (offset >= c.num_lines) {
    out.push_back(
        bad(Status::kFail, check,
            "GPIO chip " + c.name + " [" + c.label + "] has " + std::to_string(c.num_lines) +
                " lines; " + spec + " asks for line " + std::to_string(offset),
            "gpioinfo " + c.name + " lists its lines and their names (GPIO17 is header pin 11)"));
    return;
  }
  const GpioLine l = host.gpio_line(chip, offset);
  if (l.used && l.consumer != own_consumer) {
    out.push_back(
        bad(Status::kFail, check,
            "GPIO line " + std::to_string(offset) + " of " + c.name + " [" + c.label +
                "] is busy, held by '" + (l.consumer.empty() ? "(unnamed)" : l.consumer) + "'",
            "gpioinfo " + c.name +
                " shows the holder; stop it (another hullpose process? a dtoverlay such as "
                "gpio-shutdown or w1-gpio on that pin?) or wire the trigger to a free line"));
    return;
  }
  out.push_back(ok(check, "GPIO line " + std::to_string(offset) + " of " + c.name + " [" + c.label +
                              "] " + (l.used ? "held by " + own_consumer + " (running)" : "free")));
}

// --- the camera
// -----------------------------------------------------------------------------------

void check_camera(const Host& host, const CameraSetup& cam, std::vector<Result>& out) {
  const std::string check = "camera." + std::to_string(cam.camera_id);
  if (cam.source == "v4l2") {
    const std::string device = cam.device.empty() ? "/dev/video0" : cam.device;
    if (!host.exists(device))
      out.push_back(bad(Status::kFail, check,
                        "V4L2 device " + device + " of " + cam.config_file + " is absent",
                        "v4l2-ctl --list-devices; check the cable and that the driver is loaded "
                        "(dmesg | grep -i video)"));
    else
      out.push_back(ok(check, "V4L2 device " + device + " present"));
  } else if (cam.source == "libcamera") {
    const CameraList list = host.cameras();
    if (!list.probed) {
      out.push_back(skip(check, "libcamera camera list: " + list.error));
    } else if (list.ids.empty() ||
               (!cam.device.empty() &&
                cam.device.find_first_not_of("0123456789") != std::string::npos &&
                std::find(list.ids.begin(), list.ids.end(), cam.device) == list.ids.end())) {
      std::string ids;
      for (const auto& id : list.ids) ids += (ids.empty() ? "" : ", ") + id;
      out.push_back(bad(
          Status::kFail, check,
          "camera absent: libcamera lists " + (ids.empty() ? std::string("no cameras") : ids) +
              (cam.device.empty() ? "" : "; " + cam.config_file + " wants '" + cam.device + "'"),
          "rpicam-hello --list-cameras (or cam -l); check the ribbon cable and the sensor's "
          "dtoverlay in "
          "/boot/firmware/config.txt (dtoverlay=imx296 for the Global Shutter camera, imx477 for "
          "the HQ "
          "camera), then reboot"));
    } else {
      out.push_back(ok(check, "libcamera lists " + std::to_string(list.ids.size()) + " camera(s)"));
    }
  } else {
    out.push_back(skip(check, "source '" + cam.source + "' needs no camera"));
  }
  if (!cam.external_trigger) return;
  // The sensor's external-trigger switch: a module parameter (imx296: trigger_mode).
  std::string sensors;
  for (const std::string& module : host.list("/sys/module"))
    if (host.exists("/sys/module/" + module + "/parameters/trigger_mode"))
      sensors += (sensors.empty() ? "" : ", ") + module;
  if (sensors.empty())
    out.push_back(
        bad(Status::kFail, check + ".trigger_mode",
            cam.config_file +
                " asks for external_trigger, but no loaded sensor driver has a trigger_mode "
                "parameter (/sys/module/*/parameters/trigger_mode)",
            "load the Global Shutter camera's driver (dtoverlay=imx296 in "
            "/boot/firmware/config.txt, reboot), "
            "or set source.external_trigger: false and trigger.camera: free_running"));
  else
    out.push_back(
        ok(check + ".trigger_mode", "external-trigger parameter of " + sensors + " present"));
}

// --- the rig file
// ---------------------------------------------------------------------------------

void check_rig(const Host& host, const std::string& rig_file, const std::vector<int>& camera_ids,
               const std::string& rig_id, std::vector<Result>& out) {
  if (rig_file.empty()) return;
  if (!host.exists(rig_file)) {
    out.push_back(bad(Status::kFail, "rig.file", "rig file " + rig_file + " is missing",
                      "calibrate the rig (hullpose-calibrate, tools/calibrate/README.md) and copy "
                      "its rig.yaml to " +
                          rig_file + " on every board"));
    return;
  }
  try {
    const Rig rig = load_rig(host.at(rig_file));
    for (int id : camera_ids)
      if (!rig.find(id)) {
        out.push_back(bad(Status::kFail, "rig.file",
                          "rig file " + rig_file + " has no camera " + std::to_string(id),
                          "set camera_id to one of the rig's cameras, or copy the current rig.yaml "
                          "from the fusion host"));
        return;
      }
    // Camera nodes ignore announcements of another rig: every frame would be dropped as no_trigger.
    if (!rig_id.empty() && rig_id != rig.rig_id) {
      out.push_back(bad(
          Status::kFail, "rig.id",
          "HULLPOSE_RIG_ID=" + rig_id + " but " + rig_file + " is rig '" + rig.rig_id +
              "': the camera nodes ignore the trigger master's announcements and drop every frame",
          "set HULLPOSE_RIG_ID=" + rig.rig_id + " in /etc/hullpose/hullpose.conf"));
    }
    out.push_back(ok("rig.file", "rig '" + rig.rig_id + "', " + std::to_string(rig.cameras.size()) +
                                     " cameras"));
  } catch (const Error& e) {
    out.push_back(bad(Status::kFail, "rig.file", e.what(), "recalibrate or restore the rig file"));
  }
}

// --- the rig key
// ---------------------------------------------------------------------------------

// The same key file on every board, readable by the service user only: a board with another key
// (or none) has every message it sends dropped by the others as unauthenticated, counted but
// silent; RigKey::load refuses a key that group or others can read.
void check_rig_key(const Host& host, const std::string& key_file, std::vector<Result>& out) {
  const std::string install = "install -o hullpose -g hullpose -m 600 rig.key " +
                              (key_file.empty() ? std::string("/etc/hullpose/rig.key") : key_file);
  if (key_file.empty()) {
    out.push_back(bad(Status::kWarn, "rig.key",
                      "no rig key: messages are not authenticated, anything on the LAN can "
                      "send triggers and poses",
                      "on one host: hullpose-rig-key --output rig.key; on every board: " + install +
                          " and set HULLPOSE_RIG_KEY (and lcm.rig_key of camera nodes)"));
    return;
  }
  if (!host.exists(key_file)) {
    out.push_back(bad(Status::kFail, "rig.key", "rig key " + key_file + " is missing",
                      "copy the rig's key (made once by hullpose-rig-key --output rig.key) to "
                      "this board: " +
                          install));
    return;
  }
  try {
    const auth::RigKey key = auth::RigKey::load(host.at(key_file).string());
    char id[16];
    std::snprintf(id, sizeof id, "%08x", key.id());
    out.push_back(ok("rig.key", "rig key " + key_file + ", key id " + id +
                                    " (the same on every board: hullpose-rig-key --check)"));
  } catch (const Error& e) {
    out.push_back(bad(Status::kFail, "rig.key", e.what(),
                      install + " (the service user reads it, nobody else)"));
  }
}

}  // namespace

CameraSetup load_camera(const Host& host, const std::string& config_file) {
  CameraSetup c;
  c.config_file = config_file;
  try {
    const camera_node::NodeConfig cfg = camera_node::load_node_config(host.at(config_file));
    c.camera_id = cfg.camera_id;
    const std::string rig = cfg.rig_file.string(), root = host.root().string();
    c.rig_file = host.root() == "/" ? rig : "/" + fs::relative(cfg.rig_file, host.root()).string();
    c.source = cfg.source.type;
    c.device = cfg.source.params.get_string(c.source == "v4l2" ? "device" : "camera", "");
    c.external_trigger = cfg.source.params.get_bool("external_trigger", false);
    c.trigger_edges = cfg.trigger.enabled ? cfg.trigger.edges : "";
    c.lcm_url = cfg.lcm.url;
    const std::string key = cfg.lcm.rig_key.string();
    c.rig_key = key.empty() || host.root() == "/" ? key : "/" + fs::relative(key, root).string();
  } catch (const Error& e) {
    c.error = e.what();
  }
  return c;
}

Setup setup_from_etc(const Host& host, Role role) {
  Setup s;
  s.role = role;
  for (const std::string& file : host.list("/etc/hullpose")) {
    if (file.size() < 5 || file.substr(file.size() - 5) != ".conf") continue;
    const auto conf = host.read("/etc/hullpose/" + file);
    if (!conf) continue;
    std::istringstream lines(*conf);
    for (std::string line; std::getline(lines, line);) {
      line = trim(line);
      if (line.empty() || line[0] == '#') continue;
      const size_t eq = line.find('=');
      if (eq == std::string::npos) continue;
      const std::string key = trim(line.substr(0, eq));
      std::string value = trim(line.substr(eq + 1));
      if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') &&
          value.back() == value.front())
        value = value.substr(1, value.size() - 2);
      if (key == "HULLPOSE_LCM_URL") s.lcm_url = value;
      if (key == "HULLPOSE_RIG") s.rig_file = value;
      if (key == "HULLPOSE_TRIGGER_LINE") s.trigger_line = value;
      if (key == "HULLPOSE_RIG_ID") s.rig_id = value;
      if (key == "HULLPOSE_RIG_KEY") s.rig_key = value;
    }
  }
  if (role == Role::kAll || role == Role::kCameraNode)
    for (const std::string& name : host.list("/etc/hullpose"))
      if (name.rfind("camera", 0) == 0 && name.size() > 5 &&
          name.substr(name.size() - 5) == ".yaml")
        s.cameras.push_back(load_camera(host, "/etc/hullpose/" + name));
  return s;
}

std::vector<Result> run_checks(const Host& host, const Setup& setup) {
  std::vector<Result> out;
  const bool all = setup.role == Role::kAll;
  // Camera nodes carry their own LCM URL; check each distinct one (usually all the same).
  std::vector<std::string> urls;
  if (all || setup.role != Role::kCameraNode || setup.cameras.empty())
    urls.push_back(setup.lcm_url);
  for (const CameraSetup& c : setup.cameras)
    if (c.error.empty() && std::find(urls.begin(), urls.end(), c.lcm_url) == urls.end())
      urls.push_back(c.lcm_url);
  for (const std::string& url : urls) {
    Setup s = setup;
    s.lcm_url = url;
    check_network(host, s, out);
  }
  check_clock(host, out);
  if ((all || setup.role == Role::kTriggerMaster) && setup.trigger_line.rfind("gpiod:", 0) == 0)
    check_gpio(host, "trigger_master", setup.trigger_line, "hullpose-trigger-master", out);
  // The fusion host's rig file is checked once, for the cameras configured with the same file.
  const bool host_rig = all || setup.role == Role::kFusionHost ||
                        setup.role == Role::kTriggerMaster || setup.role == Role::kConsumer;
  std::vector<int> ids;
  for (const CameraSetup& c : setup.cameras) {
    if (!c.error.empty()) {
      // The node config checks its lcm.rig_key as it loads (RigKey::load's message says what).
      const bool key = c.error.find("rig key '") != std::string::npos;
      out.push_back(
          bad(Status::kFail, key ? "rig.key" : "camera.config", c.error,
              key ? "install -o hullpose -g hullpose -m 600 rig.key <the file named above> "
                    "(the rig's key, the same on every board; made once by "
                    "hullpose-rig-key --output rig.key)"
                  : "fix the field named above in " + c.config_file));
      continue;
    }
    check_camera(host, c, out);
    if (c.trigger_edges.rfind("gpiod:", 0) == 0)
      check_gpio(host, "camera" + std::to_string(c.camera_id), c.trigger_edges,
                 "hullpose-camera-node", out);
    if (!host_rig || setup.rig_file != c.rig_file)
      check_rig(host, c.rig_file, {c.camera_id}, "", out);
    else
      ids.push_back(c.camera_id);
  }
  if (host_rig) check_rig(host, setup.rig_file, ids, setup.rig_id, out);
  // The key of each process of this board, once per distinct file.
  std::vector<std::string> keys;
  if (all || setup.role != Role::kCameraNode) keys.push_back(setup.rig_key);
  for (const CameraSetup& c : setup.cameras)
    if (c.error.empty() && std::find(keys.begin(), keys.end(), c.rig_key) == keys.end())
      keys.push_back(c.rig_key);
  for (const std::string& key : keys) check_rig_key(host, key, out);
  if (setup.role == Role::kCameraNode && setup.cameras.empty())
    out.push_back(
        bad(Status::kFail, "camera.config", "no camera node config (/etc/hullpose/camera<N>.yaml)",
            "cp /etc/hullpose/camera0.yaml /etc/hullpose/camera<N>.yaml and set its camera_id"));
  return out;
}

}  // namespace hullpose::doctor
