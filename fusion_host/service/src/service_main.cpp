#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"

namespace hullpose::fusion {
namespace {
struct Options {
  std::string rig_file;
  std::string lcm_url;
  std::string rig_key;     // the rig's key file: messages authenticated (docs/messages.md)
  std::string ready_file;  // written once subscribed (for scripts that start publishers next)
  double duration_s = 0;   // 0: until a signal
  ServiceConfig service;
  PipelineOptions pipeline;
};

constexpr const char* kUsage =
    " --rig FILE [--lcm-url URL] [--rig-key FILE] [--min-cameras N] [--deadline-ms MS] "
    "[--deadline-from "
    "first|trigger]\n"
    "    [--max-open N] [--max-clock-skew-ms MS] [--duration-s S] [--ready-file FILE] "
    "[--resolution N]\n"
    "    [--tolerance K] [--backend auto|cpu|cuda] [--pose bottom-up|track] [--smooth-hz HZ (0: "
    "off)]\n"
    "    [--hull-rate HZ (0: off)] [--lag-frames 1|0 (1: one frame late, smoothed)]\n"
    "  or, offline: --replay DIR --out FILE [--resolution N] [--frames N] [--threads N]\n"
    "    [--backend auto|cpu|cuda] [--skeletoniser ck3|d6i1d] [--curve-rule ck3|isthmus|endvoxel] "
    "[--timings FILE]\n"
    "    [--pose bottom-up|track] [--smooth-hz HZ (0: off)] [--lag-frames 1|0]\n";

// Empty when --help was asked for.
std::optional<Options> parse(int argc, const char* const* argv, const char* tool) {
  Options o;
  AssemblerConfig& a = o.service.assembler;
  const auto ms_to_us = [](int64_t& out, const char* name) {
    return [&out, name](const std::string& v) {
      out = static_cast<int64_t>(cli::parse_double(name, v) * 1000);
    };
  };
  cli::CommandLine cl(std::string("usage: ") + tool + kUsage);
  cl.option("--rig", o.rig_file)
      .option("--lcm-url", o.lcm_url)
      .option("--rig-key", o.rig_key)
      .option("--min-cameras", a.min_cameras)
      .option("--deadline-ms", ms_to_us(a.deadline_us, "--deadline-ms"))
      .option("--max-clock-skew-ms", ms_to_us(a.max_clock_skew_us, "--max-clock-skew-ms"))
      .option("--max-open",
              [&a](const std::string& v) {
                const long long n = cli::parse_integer("--max-open", v);
                HULLPOSE_THROW_UNLESS(n > 0, "--max-open must be positive, got " << n);
                a.max_open = static_cast<size_t>(n);
              })
      .option("--duration-s", o.duration_s)
      .option("--ready-file", o.ready_file)
      .option("--resolution", o.pipeline.resolution)
      .option("--tolerance", o.pipeline.tolerance)
      .option("--backend", o.pipeline.backend)
      .option("--pose", o.pipeline.pose)
      .option("--smooth-hz", o.pipeline.smooth_hz)
      .option("--hull-rate", o.service.hull.rate_hz)
      .option("--lag-frames",
              [&o](const std::string& v) { o.service.lag.frames = pose::parse_lag_frames(v); })
      .option("--deadline-from", [&a](const std::string& v) {
        HULLPOSE_THROW_UNLESS(v == "first" || v == "trigger",
                              "--deadline-from must be first or trigger, got '" << v << "'");
        a.deadline_from = v == "first" ? DeadlineFrom::kFirstArrival : DeadlineFrom::kTrigger;
      });
  if (!cl.parse(argc, argv)) return std::nullopt;
  HULLPOSE_THROW_UNLESS(!o.rig_file.empty(), "--rig FILE is required (see --help)");
  HULLPOSE_THROW_UNLESS(o.pipeline.smooth_hz >= 0,
                        "--smooth-hz must not be negative (0: off), got " << o.pipeline.smooth_hz);
  HULLPOSE_THROW_UNLESS(
      o.service.hull.rate_hz >= 0 && o.service.hull.rate_hz <= 30,
      "--hull-rate must be in 0..30 hulls per second (0: off), got " << o.service.hull.rate_hz);
  return o;
}
}  // namespace

int service_main(
    int argc, const char* const* argv, const char* tool,
    const std::function<std::unique_ptr<FramePipeline>(const Rig&, const PipelineOptions&)>&
        make_pipeline) {
  const std::optional<Options> parsed = parse(argc, argv, tool);
  if (!parsed) return 0;
  const Options& o = *parsed;
  const Rig rig = load_rig(o.rig_file);
  const std::unique_ptr<bus::Bus> bus = bus::open_bus(o.lcm_url, o.rig_key);
  auto pipeline = make_pipeline(rig, o.pipeline);
  FusionService service(*bus, system_clock(), rig, *pipeline, o.service);
  if (!o.ready_file.empty()) std::ofstream(o.ready_file) << "ready\n";
  catch_stop_signals();
  const int64_t end =
      o.duration_s > 0 ? monotonic_us() + static_cast<int64_t>(o.duration_s * 1e6) : INT64_MAX;
  service.run([&] { return !stop_requested() && monotonic_us() < end; });
  std::fprintf(stderr, "%s: %lld skeletons published;", tool,
               static_cast<long long>(service.skeletons_published()));
  for (const Counters* c : {&service.assembler().counters(), &service.counters()})
    for (const auto& [name, value] : c->snapshot())
      std::fprintf(stderr, " %s=%lld", name.c_str(), static_cast<long long>(value));
  for (const auto& [name, value] : bus->drops())
    std::fprintf(stderr, " %s=%lld", name.c_str(), static_cast<long long>(value));
  std::fprintf(stderr, "\n");
  return 0;
}

}  // namespace hullpose::fusion
