// hullpose-listen: prints or records the rig's skeletons (CSV or JSON lines) with latency
// statistics. Raw traffic is recorded with lcm-logger and replayed with lcm-logplayer
// (tests/rig/lcm_log_replay_test.sh shows the round trip into the fusion host).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/joints.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/listen/skeleton_log.hpp"
#include "hullpose/msg/wire.hpp"

namespace {
const char* kUsage =
    "usage: hullpose-listen [--lcm-url URL] [--rig-key FILE] [--channel SKELETON] [--format "
    "csv|jsonl|none] "
    "[--output FILE]\n"
    "         [--estimates FILE --frame-offset K] [--summary FILE] [--count N] [--duration-s S] "
    "[--live]\n"
    "         [--ready-file FILE]\n";

struct Options {
  std::string lcm_url, rig_key, channel = "SKELETON", format = "csv", output = "-", estimates,
                                summary, ready_file;
  long long count = 0, frame_offset = 0;
  double duration_s = 0;
  bool live = false;
};

// Empty when --help was asked for.
std::optional<Options> parse(int argc, const char* const* argv) {
  Options o;
  hullpose::cli::CommandLine cl(kUsage);
  cl.option("--lcm-url", o.lcm_url)
      .option("--rig-key", o.rig_key)
      .option("--channel", o.channel)
      .option("--format", o.format)
      .option("--output", o.output)
      .option("--estimates", o.estimates)
      .option("--frame-offset", o.frame_offset)
      .option("--summary", o.summary)
      .option("--ready-file", o.ready_file)
      .option("--count", o.count)
      .option("--duration-s", o.duration_s)
      .flag("--live", o.live);
  if (!cl.parse(argc, argv)) return std::nullopt;
  HULLPOSE_THROW_UNLESS(o.format == "csv" || o.format == "jsonl" || o.format == "none",
                        "--format must be csv, jsonl or none, got '" << o.format << "'");
  return o;
}

struct Listener {
  explicit Listener(const Options& options) : o(options) {}
  const Options& o;
  std::ostream* out = nullptr;
  std::ofstream* estimates = nullptr;
  hullpose::listen::SkeletonStats stats;
  hullpose_msg::skeleton_t msg;
  int64_t dropped = 0, interval = 0;
  void on_skeleton(std::span<const uint8_t> bytes) {
    if (!hullpose::wire::decode(bytes, msg) || msg.num_joints != hullpose::kNumJoints) {
      ++dropped;
      return;
    }
    stats.add(msg);
    ++interval;
    if (o.format == "csv")
      hullpose::listen::write_csv(*out, msg);
    else if (o.format == "jsonl")
      hullpose::listen::write_jsonl(*out, msg);
    if (estimates) hullpose::listen::write_estimate(*estimates, msg, o.frame_offset);
    // Each skeleton reaches the file as it arrives (30 writes a second): a recording read while
    // it is written (a live tail, the rig tests waiting for the last trigger's row) sees every
    // skeleton heard, and a listener killed or cut off loses none. Buffered, the last rows
    // appeared only at exit, and each fault-matrix run waited out its 20 s deadline for them.
    out->flush();
    if (estimates) estimates->flush();
  }
};

int run(int argc, const char* const* argv) {
  const std::optional<Options> parsed = parse(argc, argv);
  if (!parsed) return 0;
  const Options& o = *parsed;
  const std::unique_ptr<hullpose::bus::Bus> bus = hullpose::bus::open_bus(o.lcm_url, o.rig_key);
  std::ofstream file, estimates;
  Listener l(o);
  l.out = &std::cout;
  if (o.output != "-") {
    file.open(o.output);
    HULLPOSE_THROW_UNLESS(file.good(), o.output << ": cannot write");
    l.out = &file;
  }
  if (o.format == "csv") hullpose::listen::write_csv_header(*l.out);
  if (!o.estimates.empty()) {
    estimates.open(o.estimates);
    HULLPOSE_THROW_UNLESS(estimates.good(), o.estimates << ": cannot write");
    hullpose::listen::write_estimate_header(estimates);
    l.estimates = &estimates;
  }
  const hullpose::bus::Subscription sub = bus->subscribe(
      o.channel, [&l](std::span<const uint8_t> bytes, const std::string&) { l.on_skeleton(bytes); },
      1000);
  if (!o.ready_file.empty()) std::ofstream(o.ready_file) << "ready\n";
  hullpose::catch_stop_signals();
  const int64_t start = hullpose::monotonic_us();
  const int64_t end =
      o.duration_s > 0 ? start + static_cast<int64_t>(o.duration_s * 1e6) : INT64_MAX;
  int64_t next_live = start + 1'000'000;
  while (!hullpose::stop_requested() && hullpose::monotonic_us() < end &&
         (o.count == 0 || l.stats.received() < o.count)) {
    bus->handle(100);
    const int64_t now = hullpose::monotonic_us();
    if (o.live && now >= next_live) {
      const auto& pub = l.stats.stage(4);
      std::fprintf(
          stderr,
          "hullpose-listen: %5.1f fps, %lld skeletons (%lld valid, %lld sequences missing), "
          "trigger->published p50 %.1f ms p99 %.1f ms\n",
          static_cast<double>(l.interval) * 1e6 / static_cast<double>(now - next_live + 1'000'000),
          static_cast<long long>(l.stats.received()), static_cast<long long>(l.stats.valid()),
          static_cast<long long>(l.stats.missing_sequences()), pub.percentile_ms(0.5),
          pub.percentile_ms(0.99));
      l.interval = 0;
      next_live = now + 1'000'000;
    }
  }
  l.out->flush();
  const std::string summary = l.stats.summary_json();
  if (!o.summary.empty()) std::ofstream(o.summary) << summary << "\n";
  std::string drops;
  for (const auto& [name, value] : bus->drops()) drops += " " + name + "=" + std::to_string(value);
  std::fprintf(stderr, "hullpose-listen: %s (dropped malformed: %lld;%s)\n", summary.c_str(),
               static_cast<long long>(l.dropped), drops.c_str());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-listen", argc, argv, run);
}
