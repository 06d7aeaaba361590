// hullpose-trigger-master: drives the rig's trigger line and announces every pulse on TRIGGER.
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <string>
#include <thread>

#include <hullpose_msg/node_status_t.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/firmware_sync/trigger_master.hpp"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

const char* kUsage =
    "usage: hullpose-trigger-master --rig-id ID [--rate HZ=30] [--pulse-us US=1000]\n"
    "         [--line gpiod:CHIP:OFFSET|wire:PATH|sim] [--lcm-url URL] [--count N] [--control-stdin]\n"
    "         [--wait-nodes N]   (wire: start pulsing once N camera nodes are connected, at most 60 s)\n"
    "  --control-stdin reads commands from stdin: 'stop', 'start', 'rate HZ', 'quit'.\n";

struct Options {
  hullpose::sync::TriggerMasterConfig master;
  std::string line = "gpiod:gpiochip0:17";
  std::string lcm_url;
  long long count = 0;  // 0: forever
  bool control_stdin = false;
  long long wait_nodes = 0;
};

// Empty when --help was asked for.
std::optional<Options> parse(int argc, char** argv) {
  Options o;
  hullpose::cli::CommandLine cl(kUsage);
  cl.option("--rig-id", o.master.rig_id)
      .option("--rate", o.master.rate_hz)
      .option("--pulse-us", o.master.pulse_width_us)
      .option("--line", o.line)
      .option("--lcm-url", o.lcm_url)
      .option("--count", o.count)
      .flag("--control-stdin", o.control_stdin)
      .option("--wait-nodes", o.wait_nodes);
  if (!cl.parse(argc, argv)) return std::nullopt;
  o.master.validate();
  return o;
}

void publish_status(lcm::LCM& bus, hullpose::sync::TriggerMaster& m, const std::string& rig_id, const std::string& line) {
  hullpose_msg::node_status_t s{};
  s.utime = hullpose::realtime_utime();
  s.rig_id = rig_id;
  s.role = "firmware_sync";
  s.node_id = -1;
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  s.hostname = host;
  s.state = m.running() ? hullpose_msg::node_status_t::STATE_RUNNING : hullpose_msg::node_status_t::STATE_STOPPED;
  s.message = "line " + line + ", period " + std::to_string(m.period_us()) + " us, epoch " + std::to_string(m.epoch());
  s.fps = static_cast<float>(1e6 / static_cast<double>(m.period_us()));
  s.frames_total = m.next_seq();
  s.last_trigger_seq = m.next_seq() - 1;
  s.stage_name = {"jitter_mean", "jitter_p99", "jitter_max"};
  s.stage_ms = {static_cast<float>(m.jitter().mean_us() / 1000.0), static_cast<float>(m.jitter().p99_us()) / 1000.f,
                static_cast<float>(m.jitter().max_us()) / 1000.f};
  s.num_stages = 3;
  s.counter_name = {"missed_slots"};
  s.counter_value = {m.missed_slots()};
  s.num_counters = 1;
  bus.publish("STATUS", &s);
}
}  // namespace

HULLPOSE_LOG_CATEGORY(Main, "trigger_master")

int main(int argc, char** argv) {
  try {
    if (const char* spec = std::getenv("HULLPOSE_LOG")) hullpose::log::set_levels(spec);
    const std::optional<Options> parsed = parse(argc, argv);
    if (!parsed) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    const Options& o = *parsed;
    lcm::LCM bus(o.lcm_url);
    HULLPOSE_THROW_UNLESS(bus.good(), "LCM '" << (o.lcm_url.empty() ? "default" : o.lcm_url) << "' cannot be opened");
    auto line = hullpose::sync::open_trigger_line(o.line);
    if (o.wait_nodes > 0) {
      const size_t got = line->wait_for_nodes(static_cast<size_t>(o.wait_nodes), 60'000);
      HULLPOSE_THROW_UNLESS(got >= static_cast<size_t>(o.wait_nodes),
                            "only " << got << " of " << o.wait_nodes << " camera nodes connected to " << line->describe() << " within 60 s");
    }
    hullpose::sync::SystemClock clock;
    std::vector<uint8_t> buf(4096);
    hullpose::sync::TriggerMaster master(
        o.master, *line, clock,
        [&](const hullpose_msg::trigger_t& t) {
          const int n = t.encode(buf.data(), 0, static_cast<int>(buf.size()));
          if (n > 0) bus.publish("TRIGGER", buf.data(), static_cast<unsigned>(n));
        },
        hullpose::sync::new_epoch());
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    if (o.control_stdin) {
      std::thread([&] {
        std::string cmd;
        while (std::cin >> cmd) {
          try {
            if (cmd == "stop") master.stop();
            else if (cmd == "start") master.start();
            else if (cmd == "rate") { double hz = 0; std::cin >> hz; master.set_rate(hz); }
            else if (cmd == "quit") { g_stop = 1; master.start(); }
            else std::cerr << "hullpose-trigger-master: unknown command '" << cmd << "'\n";
          } catch (const hullpose::Error& e) {
            std::cerr << "hullpose-trigger-master: " << e.what() << "\n";
          }
        }
      }).detach();
    }
    HULLPOSE_LOG(Main, Info) << "rig " << o.master.rig_id << ": " << o.master.rate_hz << " Hz on " << line->describe()
                             << ", epoch " << master.epoch();
    int64_t next_status = clock.monotonic_us();
    master.run([&] {
      if (clock.monotonic_us() >= next_status) {
        publish_status(bus, master, o.master.rig_id, line->describe());
        next_status += 1'000'000;
      }
      return !g_stop && (o.count == 0 || master.next_seq() < o.count);
    });
    publish_status(bus, master, o.master.rig_id, line->describe());
    std::fprintf(stderr, "hullpose-trigger-master: %lld pulses, jitter mean %.1f us p99 %lld us max %lld us, %lld missed slots\n",
                 static_cast<long long>(master.next_seq()), master.jitter().mean_us(),
                 static_cast<long long>(master.jitter().p99_us()), static_cast<long long>(master.jitter().max_us()),
                 static_cast<long long>(master.missed_slots()));
    return 0;
  } catch (const hullpose::Error& e) {
    std::fprintf(stderr, "hullpose-trigger-master: error: %s\n", e.what());
    return 2;
  }
}
