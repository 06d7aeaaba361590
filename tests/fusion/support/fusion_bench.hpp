#pragma once
// What the fusion benchmarks share: the scene (frames, their foreground boxes, a carver and the
// carved and cleaned hulls), the process CPU clock and the FusionCore loop with its per-stage
// counters (bench_fusion on rendered CMU frames, bench_real on the crane).
#include <benchmark/benchmark.h>

#include <ctime>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/fusion/hull_cleanup.hpp"

namespace hullpose::fusion::testing {

struct BenchScene {
  Rig rig;
  std::vector<std::vector<cv::Mat>> views;  // [frame][camera]
  // Foreground boxes, as the silhouette codec's header gives them.
  std::vector<std::vector<PixelRoi>> boxes;
  std::unique_ptr<carve::Carver> carver;
  std::vector<BitGrid> hulls;  // carved and cleaned, per frame
};

inline std::unique_ptr<BenchScene> make_bench_scene(Rig rig,
                                                    std::vector<std::vector<cv::Mat>> views,
                                                    int resolution) {
  auto s = std::make_unique<BenchScene>();
  s->rig = std::move(rig);
  s->views = std::move(views);
  for (const auto& frame : s->views) {
    auto& boxes = s->boxes.emplace_back();
    for (const cv::Mat& v : frame) {
      const cv::Rect r = cv::boundingRect(v);
      boxes.push_back({r.x, r.y, r.width, r.height});
    }
  }
  s->carver = std::make_unique<carve::Carver>(s->rig, carve::CarveOptions{resolution, 0, 1});
  HullCleanup cleanup;
  for (const auto& frame : s->views) {
    carve::CarveReport report;
    HullStats stats;
    s->carver->carve(frame, s->hulls.emplace_back(), report);
    cleanup.apply(s->hulls.back(), stats);
  }
  return s;
}

// CPU time of this process (ms): on the shared build machine wall time mostly measures the
// other jobs; cpu_ms is reported beside median_ms for that reason.
inline double cpu_now_ms() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

// Runs `core` over the frames in turn and reports cpu_ms, carve_ms, cleanup_ms, thin_ms and
// thin_iterations per frame.
template <class Views, class Boxes>
void run_fusion_core(benchmark::State& state, FusionCore& core, const std::vector<Views>& views,
                     const std::vector<Boxes>& boxes) {
  double carve_ms = 0, thin_ms = 0, cleanup_ms = 0, iterations = 0;
  size_t f = 0;
  const double cpu0 = cpu_now_ms();
  for (auto _ : state) {
    const auto& r = core.process(views[f], boxes[f]);
    f = (f + 1) % views.size();
    carve_ms += r.timings.carve_ms;
    cleanup_ms += r.timings.cleanup_ms;
    thin_ms += r.timings.thin_ms;
    iterations += r.thin.iterations;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["cpu_ms"] = (cpu_now_ms() - cpu0) / n;
  state.counters["carve_ms"] = carve_ms / n;
  state.counters["cleanup_ms"] = cleanup_ms / n;
  state.counters["thin_ms"] = thin_ms / n;
  state.counters["thin_iterations"] = iterations / n;
}

}  // namespace hullpose::fusion::testing
