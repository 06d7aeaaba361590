#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"

namespace hullpose::fusion {
namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

struct Options {
  std::string rig_file;
  std::string lcm_url;
  std::string ready_file;  // written once subscribed (for scripts that start publishers next)
  double duration_s = 0;  // 0: until a signal
  ServiceConfig service;
  PipelineOptions pipeline;
};

Options parse(int argc, char** argv) {
  static const char* usage =
      " --rig FILE [--lcm-url URL] [--min-cameras N] [--deadline-ms MS] [--deadline-from first|trigger]"
      " [--max-open N] [--max-clock-skew-ms MS] [--duration-s S] [--ready-file FILE] [--resolution N] [--tolerance K]";
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      HULLPOSE_THROW_UNLESS(i + 1 < argc, "option " << a << " needs a value; usage:" << usage);
      return argv[++i];
    };
    try {
      if (a == "--rig") o.rig_file = value();
      else if (a == "--lcm-url") o.lcm_url = value();
      else if (a == "--min-cameras") o.service.assembler.min_cameras = std::stoi(value());
      else if (a == "--deadline-ms") o.service.assembler.deadline_us = static_cast<int64_t>(std::stod(value()) * 1000);
      else if (a == "--max-open") o.service.assembler.max_open = static_cast<size_t>(std::stoul(value()));
      else if (a == "--duration-s") o.duration_s = std::stod(value());
      else if (a == "--ready-file") o.ready_file = value();
      else if (a == "--resolution") o.pipeline.resolution = std::stoi(value());
      else if (a == "--tolerance") o.pipeline.tolerance = std::stoi(value());
      else if (a == "--max-clock-skew-ms") o.service.assembler.max_clock_skew_us = static_cast<int64_t>(std::stod(value()) * 1000);
      else if (a == "--deadline-from") {
        const std::string v = value();
        HULLPOSE_THROW_UNLESS(v == "first" || v == "trigger", "--deadline-from must be first or trigger, got '" << v << "'");
        o.service.assembler.deadline_from = v == "first" ? DeadlineFrom::kFirstArrival : DeadlineFrom::kTrigger;
      } else HULLPOSE_THROW("unknown option '" << a << "'; usage:" << usage);
    } catch (const std::logic_error&) {
      HULLPOSE_THROW("option " << a << ": '" << argv[i] << "' is not a number");
    }
  }
  HULLPOSE_THROW_UNLESS(!o.rig_file.empty(), "--rig FILE is required; usage:" << usage);
  return o;
}
}  // namespace

int service_main(int argc, char** argv, const char* tool,
                 const std::function<std::unique_ptr<FramePipeline>(const Rig&, const PipelineOptions&)>& make_pipeline) {
  try {
    if (const char* spec = std::getenv("HULLPOSE_LOG")) log::set_levels(spec);
    const Options o = parse(argc, argv);
    const Rig rig = load_rig(o.rig_file);
    lcm::LCM bus(o.lcm_url);
    HULLPOSE_THROW_UNLESS(bus.good(), "LCM '" << (o.lcm_url.empty() ? "default" : o.lcm_url) << "' cannot be opened");
    auto pipeline = make_pipeline(rig, o.pipeline);
    FusionService service(bus, rig, *pipeline, o.service);
    if (!o.ready_file.empty()) std::ofstream(o.ready_file) << "ready\n";
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const int64_t end = o.duration_s > 0 ? monotonic_us() + static_cast<int64_t>(o.duration_s * 1e6) : INT64_MAX;
    service.run([&] { return !g_stop && monotonic_us() < end; });
    std::fprintf(stderr, "%s: %lld skeletons published;", tool, static_cast<long long>(service.skeletons_published()));
    for (const Counters* c : {&service.assembler().counters(), &service.counters()})
      for (const auto& [name, value] : c->snapshot()) std::fprintf(stderr, " %s=%lld", name.c_str(), static_cast<long long>(value));
    std::fprintf(stderr, "\n");
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", tool, e.what());
    return 2;
  }
}

}  // namespace hullpose::fusion
