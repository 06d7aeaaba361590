// main() for every benchmark executable: Google Benchmark with a reporter that prints one
// JSON object per benchmark: {"name", "median_ms", "iterations", counters..., "peer"}.
// A benchmark names the benchmark it is compared with by setting its label to "peer=<name>";
// tools/bench/merge_peers.py then adds peer_median_ms and speedup.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace {

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

class JsonLinesReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      const bool median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
      const bool single = run.run_type == Run::RT_Iteration && run.repetitions <= 1;
      if (!median && !single) continue;
      if (run.error_occurred) {
        std::printf("{\"name\": \"%s\", \"error\": \"%s\"}\n",
                    json_escape(run.run_name.str()).c_str(),
                    json_escape(run.error_message).c_str());
        continue;
      }
      const double ms =
          run.GetAdjustedRealTime() / benchmark::GetTimeUnitMultiplier(run.time_unit) * 1e3;
      // cpu_ms: this thread's CPU time, the figure to read on a shared, loaded machine.
      const double cpu_ms =
          run.GetAdjustedCPUTime() / benchmark::GetTimeUnitMultiplier(run.time_unit) * 1e3;
      std::string line = "{\"name\": \"" + json_escape(run.run_name.str()) +
                         "\", \"median_ms\": " + fmt(ms) + ", \"cpu_ms\": " + fmt(cpu_ms) +
                         (median ? ", \"repetitions\": " + std::to_string(run.repetitions)
                                 : ", \"iterations\": " + std::to_string(run.iterations));
      for (const auto& [key, counter] : run.counters)
        line += ", \"" + json_escape(key) + "\": " + fmt(counter.value);
      if (run.report_label.rfind("peer=", 0) == 0)
        line += ", \"peer\": \"" + json_escape(run.report_label.substr(5)) + "\"";
      else if (!run.report_label.empty())
        line += ", \"label\": \"" + json_escape(run.report_label) + "\"";
      std::printf("%s}\n", line.c_str());
      std::fflush(stdout);
    }
  }

 private:
  static std::string fmt(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  JsonLinesReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
