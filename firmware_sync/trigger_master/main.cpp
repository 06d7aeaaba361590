// hullpose-trigger-master: drives the rig's trigger line and announces every pulse on TRIGGER.
#include <poll.h>
#include <unistd.h>

#include <cstdio>
#include <hullpose_msg/node_status_t.hpp>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/clock.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/firmware_sync/trigger_master.hpp"
#include "hullpose/msg/wire.hpp"

namespace {
const char* kUsage =
    "usage: hullpose-trigger-master --rig-id ID [--rate HZ=30] [--pulse-us US=1000]\n"
    "         [--line gpiod:CHIP:OFFSET|wire:PATH|sim] [--lcm-url URL] [--rig-key FILE] [--count "
    "N] "
    "[--control-stdin]\n"
    "         [--wait-nodes N]   (wire: start pulsing once N camera nodes are connected, at most "
    "60 s)\n"
    "  --control-stdin reads commands from stdin: 'stop', 'start', 'rate HZ', 'quit'.\n";

struct Options {
  hullpose::sync::TriggerMasterConfig master;
  std::string line = "gpiod:gpiochip0:17";
  std::string lcm_url;
  std::string rig_key;  // the rig's key file: TRIGGER and STATUS signed (docs/messages.md)
  long long count = 0;  // 0: forever
  bool control_stdin = false;
  long long wait_nodes = 0;
};

// Empty when --help was asked for.
std::optional<Options> parse(int argc, const char* const* argv) {
  Options o;
  hullpose::cli::CommandLine cl(kUsage);
  cl.option("--rig-id", o.master.rig_id)
      .option("--rate", o.master.rate_hz)
      .option("--pulse-us", o.master.pulse_width_us)
      .option("--line", o.line)
      .option("--lcm-url", o.lcm_url)
      .option("--rig-key", o.rig_key)
      .option("--count", o.count)
      .flag("--control-stdin", o.control_stdin)
      .option("--wait-nodes", o.wait_nodes);
  if (!cl.parse(argc, argv)) return std::nullopt;
  o.master.validate();
  return o;
}

void publish_status(hullpose::bus::Bus& bus, hullpose::sync::TriggerMaster& m,
                    const std::string& rig_id, const std::string& line) {
  hullpose_msg::node_status_t s{};
  s.utime = hullpose::realtime_utime();
  s.rig_id = rig_id;
  s.role = "firmware_sync";
  s.node_id = -1;
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  s.hostname = host;
  s.state = m.running() ? hullpose_msg::node_status_t::STATE_RUNNING
                        : hullpose_msg::node_status_t::STATE_STOPPED;
  s.message = "line " + line + ", period " + std::to_string(m.period_us()) + " us, epoch " +
              std::to_string(m.epoch());
  s.fps = static_cast<float>(1e6 / static_cast<double>(m.period_us()));
  s.frames_total = m.next_seq();
  s.last_trigger_seq = m.next_seq() - 1;
  s.stage_name = {"jitter_mean", "jitter_p99", "jitter_max"};
  s.stage_ms = {static_cast<float>(m.jitter().mean_us() / 1000.0),
                static_cast<float>(m.jitter().p99_us()) / 1000.f,
                static_cast<float>(m.jitter().max_us()) / 1000.f};
  s.num_stages = 3;
  s.counter_name = {"missed_slots"};
  s.counter_value = {m.missed_slots()};
  s.num_counters = 1;
  hullpose::wire::publish(bus, "STATUS", s);
}

HULLPOSE_LOG_CATEGORY(Main, "trigger_master")

// --control-stdin: commands on stdin, read by a thread that run() joins before the master it
// drives goes out of scope (it polls stdin and stops when asked, instead of blocking in a read
// that would outlive the master).
class StdinControl {
 public:
  explicit StdinControl(hullpose::sync::TriggerMaster& master)
      : thread_([this, &master](std::stop_token stop) { loop(stop, master); }) {}

 private:
  static void handle(const std::string& line, hullpose::sync::TriggerMaster& master) {
    std::istringstream in(line);
    std::string cmd;
    if (!(in >> cmd)) return;
    try {
      if (cmd == "stop") {
        master.stop();
      } else if (cmd == "start") {
        master.start();
      } else if (cmd == "rate") {
        double hz = 0;
        in >> hz;
        master.set_rate(hz);
      } else if (cmd == "quit") {
        hullpose::request_stop();
        master.start();  // wakes a stopped master so that run() sees the stop
      } else {
        std::cerr << "hullpose-trigger-master: unknown command '" << cmd << "'\n";
      }
    } catch (const hullpose::Error& e) {
      std::cerr << "hullpose-trigger-master: " << e.what() << "\n";
    }
  }

  static void loop(const std::stop_token& stop, hullpose::sync::TriggerMaster& master) {
    std::string pending;
    char buf[256];
    while (!stop.stop_requested()) {
      pollfd p{STDIN_FILENO, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
      if (n <= 0) return;  // end of input: no more commands
      pending.append(buf, static_cast<size_t>(n));
      for (size_t eol; (eol = pending.find('\n')) != std::string::npos; pending.erase(0, eol + 1))
        handle(pending.substr(0, eol), master);
    }
  }

  std::jthread thread_;  // joined (stop requested first) when the StdinControl goes
};

int run(int argc, const char* const* argv) {
  const std::optional<Options> parsed = parse(argc, argv);
  if (!parsed) return 0;
  const Options& o = *parsed;
  const std::unique_ptr<hullpose::bus::Bus> bus = hullpose::bus::open_bus(o.lcm_url, o.rig_key);
  auto line = hullpose::sync::open_trigger_line(o.line);
  if (o.wait_nodes > 0) {
    const size_t got = line->wait_for_nodes(static_cast<size_t>(o.wait_nodes), 60'000);
    HULLPOSE_THROW_UNLESS(got >= static_cast<size_t>(o.wait_nodes),
                          "only " << got << " of " << o.wait_nodes << " camera nodes connected to "
                                  << line->describe() << " within 60 s");
  }
  hullpose::Clock& clock = hullpose::system_clock();
  std::vector<uint8_t> buf(4096);
  hullpose::sync::TriggerMaster master(
      o.master, *line, clock,
      [&](const hullpose_msg::trigger_t& t) { hullpose::wire::publish(*bus, "TRIGGER", t, buf); },
      hullpose::sync::new_epoch());
  hullpose::catch_stop_signals();
  std::optional<StdinControl> control;
  if (o.control_stdin) control.emplace(master);
  HULLPOSE_LOG(Main, Info) << "rig " << o.master.rig_id << ": " << o.master.rate_hz << " Hz on "
                           << line->describe() << ", epoch " << master.epoch();
  int64_t next_status = clock.monotonic_us();
  master.run([&] {
    if (clock.monotonic_us() >= next_status) {
      publish_status(*bus, master, o.master.rig_id, line->describe());
      next_status += 1'000'000;
    }
    return !hullpose::stop_requested() && (o.count == 0 || master.next_seq() < o.count);
  });
  publish_status(*bus, master, o.master.rig_id, line->describe());
  std::fprintf(stderr,
               "hullpose-trigger-master: %lld pulses, jitter mean %.1f us p99 %lld us max %lld us, "
               "%lld missed slots\n",
               static_cast<long long>(master.next_seq()), master.jitter().mean_us(),
               static_cast<long long>(master.jitter().p99_us()),
               static_cast<long long>(master.jitter().max_us()),
               static_cast<long long>(master.missed_slots()));
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-trigger-master", argc, argv, run);
}
