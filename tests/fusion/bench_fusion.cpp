// Fusion core benchmarks (issue 4). Scene: a capsule human rendered with a thesis-like rig
// (8 cameras, 800x600) until the synthetic rig and CMU 55_01 are on main.
//   carve/N        hierarchical carving, 1 thread        peer: carve_brute/N (brute force, 1 thread)
//   ck3/N          CK3 (thesis curve rule), 1 thread     peer: skimage/skeletonize_3d/N
//   ck3/N/threads:2
//   d6i1d/N        D6I1D, 1 thread                       peer: skimage/skeletonize_3d/N
//   fusion/N       carve + clean-up + CK3 + skeleton list, 1 thread (goal: 1 ms at 64, 5 ms at 128)
//   fusion/N/threads:2
// carve/N and fusion/N get the silhouettes' foreground boxes (the fusion host has them from the
// silhouette codec's header), so no full-image scan is timed.
// The thinning input (the cleaned hull) is written to BUILD/bench/volumes/hull_N.npy for the
// scikit-image peer (tools/bench/peers/skimage_skeletonize.py).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "hullpose/fusion/fusion_core.hpp"
#include "support/synthetic_scene.hpp"

namespace {

using namespace hullpose;
namespace ft = hullpose::fusion::testing;

struct Scene {
  Rig rig;
  std::vector<cv::Mat> views;
  std::vector<PixelRoi> boxes;  // foreground boxes, as the silhouette codec's header gives them
  std::unique_ptr<carve::Carver> carver;
  fusion::BitGrid hull;  // carved and cleaned
};

// Writes a uint8 volume as .npy, C order (z, y, x).
void write_npy(const fusion::BitGrid& v, const std::filesystem::path& path) {
  std::filesystem::create_directories(path.parent_path());
  const Eigen::Vector3i d = v.dims();
  std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': (" + std::to_string(d.z()) + ", " +
                       std::to_string(d.y()) + ", " + std::to_string(d.x()) + "), }";
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::ofstream f(path, std::ios::binary);
  f.write("\x93NUMPY\x01\x00", 8);
  const uint16_t len = static_cast<uint16_t>(header.size());
  f.put(static_cast<char>(len & 0xff));
  f.put(static_cast<char>(len >> 8));
  f << header;
  std::vector<char> data(v.dims().prod());
  size_t i = 0;
  for (int z = 0; z < d.z(); ++z)
    for (int y = 0; y < d.y(); ++y)
      for (int x = 0; x < d.x(); ++x) data[i++] = v.get(x, y, z) ? 1 : 0;
  f.write(data.data(), static_cast<std::streamsize>(data.size()));
}

Scene& scene(int resolution) {
  static std::map<int, std::unique_ptr<Scene>> scenes;
  auto& s = scenes[resolution];
  if (!s) {
    s = std::make_unique<Scene>();
    s->rig = ft::thesis_like_rig(800, 600, 8);
    s->views = ft::render_views(s->rig, ft::human_capsules(0.3, 0.5, {100, -50}));
    for (const cv::Mat& v : s->views) {
      const cv::Rect r = cv::boundingRect(v);
      s->boxes.push_back({r.x, r.y, r.width, r.height});
    }
    s->carver = std::make_unique<carve::Carver>(s->rig, carve::CarveOptions{resolution, 0, 1});
    carve::CarveReport report;
    s->carver->carve(s->views, s->hull, report);
    fusion::HullStats stats;
    fusion::HullCleanup().apply(s->hull, stats);
    write_npy(s->hull, std::filesystem::path(HULLPOSE_BINARY_DIR) / "bench" / "volumes" /
                           ("hull_" + std::to_string(resolution) + ".npy"));
  }
  return *s;
}

void carve_fast(benchmark::State& state, int res) {
  Scene& s = scene(res);
  fusion::BitGrid hull;
  carve::CarveReport report;
  for (auto _ : state) s.carver->carve(s.views, hull, report, s.boxes);
  state.counters["voxels"] = static_cast<double>(report.voxels);
  state.SetLabel("peer=carve_brute/" + std::to_string(res));
}

void carve_brute(benchmark::State& state, int res) {
  Scene& s = scene(res);
  fusion::BitGrid hull;
  carve::CarveReport report;
  for (auto _ : state) s.carver->carve_brute_force(s.views, hull, report);
  state.counters["voxels"] = static_cast<double>(report.voxels);
}

void ck3(benchmark::State& state, int res, int threads) {
  Scene& s = scene(res);
  thin::Ck3Thinner thinner({thin::CurveRule::kCk3, thin::ZeroCliqueTest::kSpan3, threads, 0});
  fusion::BitGrid v;
  thin::ThinStats st;
  for (auto _ : state) {
    v = s.hull;
    st = thinner.thin(v);
  }
  state.counters["hull_voxels"] = static_cast<double>(st.initial_voxels);
  state.counters["skeleton_voxels"] = static_cast<double>(st.final_voxels);
  state.counters["thin_iterations"] = st.iterations;
  state.counters["visited"] = static_cast<double>(st.visited);
  state.SetLabel("peer=skimage/skeletonize_3d/" + std::to_string(res));
}

void d6i1d(benchmark::State& state, int res) {
  Scene& s = scene(res);
  thin::D6i1dThinner thinner;
  fusion::BitGrid v;
  thin::ThinStats st;
  for (auto _ : state) {
    v = s.hull;
    st = thinner.thin(v);
  }
  state.counters["skeleton_voxels"] = static_cast<double>(st.final_voxels);
  state.counters["thin_iterations"] = st.iterations;
  state.SetLabel("peer=skimage/skeletonize_3d/" + std::to_string(res));
}

void fusion_core(benchmark::State& state, int res, int threads) {
  Scene& s = scene(res);
  fusion::FusionOptions opt;
  opt.resolution = res;
  opt.threads = threads;
  fusion::FusionCore core(s.rig, opt);
  double carve_ms = 0, thin_ms = 0, cleanup_ms = 0;
  for (auto _ : state) {
    const auto& r = core.process(s.views, s.boxes);
    carve_ms += r.timings.carve_ms;
    cleanup_ms += r.timings.cleanup_ms;
    thin_ms += r.timings.thin_ms;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["carve_ms"] = carve_ms / n;
  state.counters["cleanup_ms"] = cleanup_ms / n;
  state.counters["thin_ms"] = thin_ms / n;
}

const bool registered = [] {
  for (int res : {64, 128}) {
    const std::string r = std::to_string(res);
    benchmark::RegisterBenchmark(("carve/" + r).c_str(), carve_fast, res)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("carve_brute/" + r).c_str(), carve_brute, res)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("ck3/" + r).c_str(), ck3, res, 1)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("ck3/" + r + "/threads:2").c_str(), ck3, res, 2)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("d6i1d/" + r).c_str(), d6i1d, res)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("fusion/" + r).c_str(), fusion_core, res, 1)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("fusion/" + r + "/threads:2").c_str(), fusion_core, res, 2)->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
