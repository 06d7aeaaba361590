// main() for every benchmark executable: Google Benchmark with a reporter that prints one
// JSON object per benchmark: {"name", "median_ms", "iterations", counters..., "peer"}.
// A benchmark names the benchmark it is compared with by setting its label to "peer=<name>";
// tools/bench/merge_peers.py then adds peer_median_ms and speedup.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

namespace {

class JsonLinesReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      const bool median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
      const bool single = run.run_type == Run::RT_Iteration && run.repetitions <= 1;
      if (!median && !single) continue;
      nlohmann::ordered_json line;
      line["name"] = run.run_name.str();
      if (run.error_occurred) {
        line["error"] = run.error_message;
        print(line);
        continue;
      }
      const double unit = benchmark::GetTimeUnitMultiplier(run.time_unit);
      line["median_ms"] = figure(run.GetAdjustedRealTime() / unit * 1e3);
      // cpu_ms: this thread's CPU time, the figure to read on a shared, loaded machine.
      line["cpu_ms"] = figure(run.GetAdjustedCPUTime() / unit * 1e3);
      if (median)
        line["repetitions"] = run.repetitions;
      else
        line["iterations"] = run.iterations;
      for (const auto& [key, counter] : run.counters) line[key] = figure(counter.value);
      if (run.report_label.rfind("peer=", 0) == 0)
        line["peer"] = run.report_label.substr(5);
      else if (!run.report_label.empty())
        line["label"] = run.report_label;
      print(line);
    }
  }

 private:
  // Six significant digits (the benchmarks' noise is far larger); null for NaN or infinity.
  static nlohmann::ordered_json figure(double v) {
    if (!std::isfinite(v)) return nullptr;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return std::strtod(buf, nullptr);
  }
  static void print(const nlohmann::ordered_json& line) {
    std::printf("%s\n",
                line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
    std::fflush(stdout);
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
