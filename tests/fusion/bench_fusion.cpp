// Fusion core benchmarks (issue 4) on CMU 55_01 (the thesis' dance-whirl) rendered by
// hullpose_synth with the thesis rig (8 cameras, 800x600): 8 frames spread over the clip, one
// frame per benchmark iteration in turn.
//   carve/N        hierarchical carving, 1 thread        peer: carve_brute/N (brute force, 1
//   thread) ck3/N          CK3 (thesis curve rule), 1 thread     peer: skimage/skeletonize_3d/N
//   ck3/N/threads:2
//   d6i1d/N        D6I1D, 1 thread                       peer: skimage/skeletonize_3d/N
//   fusion/N       carve + clean-up + CK3 + skeleton list, 1 thread (goal: 1 ms at 64, 5 ms at 128)
//   fusion/N/threads:2
//   cuda/carve/N, cuda/ck3/N  (N = 64, 128, 256; only where a CUDA device is present) the CUDA
//                  backend, with per-stage GPU times (CUDA events): upload_ms, kernels_ms,
//                  download_ms; peers: carve/N and ck3/N (the CPU), none at 256
// carve/N and fusion/N get the silhouettes' foreground boxes (the fusion host has them from the
// silhouette codec's header), so no full-image scan is timed.
// The thinning inputs (the cleaned hulls) are written to BUILD/bench/volumes/hull_N_fF.npy for
// the scikit-image peer (tools/bench/peers/skimage_skeletonize.py).
#include <benchmark/benchmark.h>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/gpu/backend.hpp"
#include "hullpose/gpu/cuda_fusion.hpp"
#include "support/cmu_scene.hpp"
#include "support/fusion_bench.hpp"

namespace {

using namespace hullpose;
namespace ft = hullpose::fusion::testing;
using ft::cpu_now_ms;

using Scene = ft::BenchScene;

// Writes a uint8 volume as .npy, C order (z, y, x).
void write_npy(const fusion::BitGrid& v, const std::filesystem::path& path) {
  std::filesystem::create_directories(path.parent_path());
  const Eigen::Vector3i d = v.dims();
  std::string header = "{'descr': '|u1', 'fortran_order': False, 'shape': (" +
                       std::to_string(d.z()) + ", " + std::to_string(d.y()) + ", " +
                       std::to_string(d.x()) + "), }";
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

const ft::CmuFrames& cmu() {
  static const ft::CmuFrames frames = ft::render_cmu_55_01(8);
  return frames;
}

Scene& scene(int resolution) {
  static std::map<int, std::unique_ptr<Scene>> scenes;
  auto& s = scenes[resolution];
  if (!s) {
    s = ft::make_bench_scene(cmu().rig, cmu().views, resolution);
    // The skimage peer thins the same hulls (tools/bench/peers/skimage_skeletonize.py).
    for (size_t f = 0; f < s->hulls.size(); ++f)
      write_npy(s->hulls[f], std::filesystem::path(HULLPOSE_BINARY_DIR) / "bench" / "volumes" /
                                 ("hull_" + std::to_string(resolution) + "_f" +
                                  std::to_string(cmu().frames[f]) + ".npy"));
  }
  return *s;
}

// Hull voxels summed over all frames of the scene: the same figure for a bench and its peer
// (the last iteration's frame depends on the iteration count).
size_t hull_voxels_all_frames(Scene& s, bool brute) {
  fusion::BitGrid hull;
  carve::CarveReport report;
  size_t total = 0;
  for (size_t f = 0; f < s.views.size(); ++f) {
    if (brute)
      s.carver->carve_brute_force(s.views[f], hull, report);
    else
      s.carver->carve(s.views[f], hull, report, s.boxes[f]);
    total += report.voxels;
  }
  return total;
}

void carve_fast(benchmark::State& state, int res) {
  Scene& s = scene(res);
  fusion::BitGrid hull;
  carve::CarveReport report;
  size_t f = 0;
  const double cpu0 = cpu_now_ms();
  for (auto _ : state) {
    s.carver->carve(s.views[f], hull, report, s.boxes[f]);
    f = (f + 1) % s.views.size();
  }
  state.counters["cpu_ms"] = (cpu_now_ms() - cpu0) / static_cast<double>(state.iterations());
  state.counters["voxels"] = static_cast<double>(hull_voxels_all_frames(s, false));
  state.SetLabel("peer=carve_brute/" + std::to_string(res));
}

void carve_brute(benchmark::State& state, int res) {
  Scene& s = scene(res);
  fusion::BitGrid hull;
  carve::CarveReport report;
  size_t f = 0;
  const double cpu0 = cpu_now_ms();
  for (auto _ : state) {
    s.carver->carve_brute_force(s.views[f], hull, report);
    f = (f + 1) % s.views.size();
  }
  state.counters["cpu_ms"] = (cpu_now_ms() - cpu0) / static_cast<double>(state.iterations());
  state.counters["voxels"] = static_cast<double>(hull_voxels_all_frames(s, true));
}

// Thins the scene's hulls in turn, one per iteration (copying the hull is timed with it);
// sets cpu_ms and returns the last frame's statistics.
template <typename Thinner>
thin::ThinStats thin_hulls(benchmark::State& state, const Scene& s, Thinner& thinner) {
  fusion::BitGrid v;
  thin::ThinStats st;
  size_t f = 0;
  const double cpu0 = cpu_now_ms();
  for (auto _ : state) {
    v = s.hulls[f];
    st = thinner.thin(v);
    f = (f + 1) % s.hulls.size();
  }
  state.counters["cpu_ms"] = (cpu_now_ms() - cpu0) / static_cast<double>(state.iterations());
  return st;
}

void ck3(benchmark::State& state, int res, int threads) {
  Scene& s = scene(res);
  thin::Ck3Thinner thinner({thin::CurveRule::kCk3, thin::ZeroCliqueTest::kSpan3, threads, 0});
  const thin::ThinStats st = thin_hulls(state, s, thinner);
  state.counters["hull_voxels"] = static_cast<double>(st.initial_voxels);
  state.counters["skeleton_voxels"] = static_cast<double>(st.final_voxels);
  state.counters["thin_iterations"] = st.iterations;
  state.counters["visited"] = static_cast<double>(st.visited);
  state.SetLabel("peer=skimage/skeletonize_3d/" + std::to_string(res));
}

void d6i1d(benchmark::State& state, int res) {
  Scene& s = scene(res);
  thin::D6i1dThinner thinner;
  const thin::ThinStats st = thin_hulls(state, s, thinner);
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
  ft::run_fusion_core(state, core, s.views, s.boxes);
}

// The GPU's own stage timings (upload, kernels, download), as per-iteration counters.
struct StageTimeSum {
  gpu::GpuStageTimes sum;
  void add(const gpu::GpuStageTimes& t) {
    sum.upload_ms += t.upload_ms;
    sum.kernels_ms += t.kernels_ms;
    sum.download_ms += t.download_ms;
  }
  void report(benchmark::State& state) const {
    const double n = static_cast<double>(state.iterations());
    state.counters["upload_ms"] = sum.upload_ms / n;
    state.counters["kernels_ms"] = sum.kernels_ms / n;
    state.counters["download_ms"] = sum.download_ms / n;
  }
};

void cuda_carve(benchmark::State& state, int res) {
  Scene& s = scene(res);
  gpu::CudaFusion cuda(*s.carver, {});
  fusion::BitGrid hull;
  carve::CarveReport report;
  StageTimeSum sum;
  size_t f = 0;
  for (auto _ : state) {
    cuda.carve(s.views[f], hull, report, s.boxes[f]);
    f = (f + 1) % s.views.size();
    sum.add(cuda.carve_times());
  }
  sum.report(state);
  if (res <= 128) state.SetLabel("peer=carve/" + std::to_string(res));
}

void cuda_ck3(benchmark::State& state, int res) {
  Scene& s = scene(res);
  gpu::CudaFusion cuda(*s.carver, {});
  fusion::BitGrid v;
  thin::ThinStats st;
  StageTimeSum sum;
  size_t f = 0;
  for (auto _ : state) {
    v = s.hulls[f];
    st = cuda.thin(v);
    f = (f + 1) % s.hulls.size();
    sum.add(cuda.thin_times());
  }
  sum.report(state);
  state.counters["thin_iterations"] = st.iterations;
  if (res <= 128) state.SetLabel("peer=ck3/" + std::to_string(res));
}

const bool registered = [] {
  for (int res : {64, 128}) {
    const std::string r = std::to_string(res);
    benchmark::RegisterBenchmark(("carve/" + r).c_str(), carve_fast, res)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("carve_brute/" + r).c_str(), carve_brute, res)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("ck3/" + r).c_str(), ck3, res, 1)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("ck3/" + r + "/threads:2").c_str(), ck3, res, 2)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("d6i1d/" + r).c_str(), d6i1d, res)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("fusion/" + r).c_str(), fusion_core, res, 1)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("fusion/" + r + "/threads:2").c_str(), fusion_core, res, 2)
        ->Unit(benchmark::kMillisecond);
  }
  // The CUDA backend where a device is present (bench_fusion runs unchanged without one).
  if (gpu::probe_device().available)
    for (int res : {64, 128, 256}) {
      const std::string r = std::to_string(res);
      benchmark::RegisterBenchmark(("cuda/carve/" + r).c_str(), cuda_carve, res)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(("cuda/ck3/" + r).c_str(), cuda_ck3, res)
          ->Unit(benchmark::kMillisecond);
    }
  return true;
}();

}  // namespace
