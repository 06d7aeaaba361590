// Background subtraction: accuracy and speed per method, on one core.
//
// bgs/<method>/synthetic/<W>x<H>: a camera of the synthetic rig (synth/: textured room,
// walking avatar, soft shadows from two lamps, illumination drift, sensor noise; 30 empty-room
// frames to learn from, 30 frames scored against the exact masks). Counters: precision, recall,
// f1 of the published mask (after the node's clean-up) over every test frame, raw_f1 before the
// clean-up; median_ms is the subtraction alone per frame (wall clock), cpu_ms the same in this
// thread's CPU time. Goals at 640x480 (issue 6):
// horprasert <= 2 ms, codebook <= 5 ms, sobs <= 12 ms, each with f1 >= mog2's.
// bgs/cleanup/<W>x<H>: the clean-up (opening, closing, small-blob removal) per frame.
// bgs/<method>/shared/<sequence>: every folder under ../shared/data/bgs holding
// background_NNNNNN.png (empty scene), rgb_NNNNNN.png and mask_NNNNNN.png (ground truth; frames
// without a mask are processed but not scored), at its own resolution.
#include <benchmark/benchmark.h>

#include <ctime>
#include <filesystem>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hullpose/camera_node/background_subtractor.hpp"
#include "hullpose/camera_node/mask_cleanup.hpp"
#include "mask_score.hpp"
#include "synth_sequence.hpp"

namespace {

using namespace hullpose;
using namespace hullpose::camera_node;
namespace fs = std::filesystem;

const CleanupParams kCleanup{};  // the node's defaults

struct Sequence {
  std::vector<cv::Mat> background, frames, truth;  // truth[i] empty: frame i not scored
};

Sequence synthetic(cv::Size size) {
  test::SynthSequenceOptions o;
  o.size = size;
  o.drift = 0.12;
  o.shadow_strength = 0.6;
  o.noise_sigma = 2.5;
  test::SynthSequence r = test::render_synth_sequence(o);
  return Sequence{std::move(r.background), std::move(r.frames), std::move(r.truth)};
}

std::string indexed(const fs::path& dir, const char* stem, int i) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%06d.png", stem, i);
  return (dir / name).string();
}

Sequence from_disk(const fs::path& dir) {
  Sequence s;
  for (int k = 0; fs::exists(indexed(dir, "background", k)); ++k)
    s.background.push_back(cv::imread(indexed(dir, "background", k)));
  for (int f = 0; fs::exists(indexed(dir, "rgb", f)); ++f) {
    s.frames.push_back(cv::imread(indexed(dir, "rgb", f)));
    const std::string mask = indexed(dir, "mask", f);
    s.truth.push_back(fs::exists(mask) ? cv::imread(mask, cv::IMREAD_GRAYSCALE) : cv::Mat());
  }
  return s;
}

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

void run(benchmark::State& state, const std::string& method, const std::string& what,
         const Sequence& seq) {
  cv::setNumThreads(1);
  if (seq.background.empty() || seq.frames.empty()) {
    state.SkipWithError("sequence has no background or no frames");
    return;
  }
  const cv::Size size = seq.frames[0].size();
  auto bgs = make_subtractor(method, Params("bgs.params"));
  bgs->begin_learning(size);
  for (const cv::Mat& b : seq.background) bgs->learn(b);
  bgs->end_learning();
  MaskCleanup cleanup(kCleanup);
  test::Score raw, post;
  cv::Mat mask(size, CV_8UC1);
  for (size_t f = 0; f < seq.frames.size(); ++f) {
    bgs->apply(seq.frames[f], mask);
    if (!seq.truth[f].empty()) raw.add(mask, seq.truth[f]);
    cleanup.apply(mask);
    if (!seq.truth[f].empty()) post.add(mask, seq.truth[f]);
  }
  size_t f = 0;
  const double cpu_start = thread_cpu_ms();
  for (auto _ : state) {
    bgs->apply(seq.frames[f], mask);
    benchmark::DoNotOptimize(mask.data);
    f = (f + 1) % seq.frames.size();
  }
  // This thread's CPU time per frame: on a shared machine it is steadier than median_ms (wall).
  state.counters["cpu_ms"] =
      (thread_cpu_ms() - cpu_start) / static_cast<double>(state.iterations());
  state.counters["precision"] = post.precision();
  state.counters["recall"] = post.recall();
  state.counters["f1"] = post.f1();
  state.counters["raw_f1"] = raw.f1();
  if (method != "mog2") state.SetLabel("peer=bgs/mog2/" + what);
}

void cleanup_bench(benchmark::State& state, cv::Size size) {
  cv::setNumThreads(1);
  const Sequence seq = synthetic(size);
  MaskCleanup cleanup(kCleanup);
  cv::Mat mask;
  size_t f = 0;
  for (auto _ : state) {
    state.PauseTiming();
    seq.truth[f].copyTo(mask);
    for (int i = 0; i < 8;
         ++i)  // specks all over the image that survive the opening, removed by area
      mask(cv::Rect((i * 97) % (size.width - 8), (i * 61) % (size.height - 8), 4, 4)).setTo(255);
    state.ResumeTiming();
    cleanup.apply(mask);
    f = (f + 1) % seq.truth.size();
  }
}

// Sequences are built once per resolution and shared by the methods.
const Sequence& synthetic_cached(cv::Size size) {
  static std::map<std::pair<int, int>, Sequence> cache;
  auto it = cache.find({size.width, size.height});
  if (it == cache.end())
    it = cache.emplace(std::pair{size.width, size.height}, synthetic(size)).first;
  return it->second;
}

const bool registered = [] {
  const char* methods[] = {"mog2", "horprasert", "codebook", "sobs", "knn"};
  for (const cv::Size size : {cv::Size(640, 480), cv::Size(800, 600)}) {
    const std::string res = std::to_string(size.width) + "x" + std::to_string(size.height);
    for (const char* m : methods) {
      const std::string method = m;
      const std::string what = "synthetic/" + res;
      benchmark::RegisterBenchmark(("bgs/" + method + "/" + what).c_str(),
                                   [method, what, size](benchmark::State& st) {
                                     run(st, method, what, synthetic_cached(size));
                                   })
          ->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark(("bgs/cleanup/" + res).c_str(), [size](benchmark::State& st) {
      cleanup_bench(st, size);
    })->Unit(benchmark::kMillisecond);
  }
  const fs::path shared = fs::path(HULLPOSE_SHARED_DIR) / "data" / "bgs";
  std::error_code ec;
  if (fs::is_directory(shared, ec)) {
    for (const auto& entry : fs::recursive_directory_iterator(shared, ec)) {
      if (!entry.is_directory() || !fs::exists(indexed(entry.path(), "rgb", 0))) continue;
      const fs::path dir = entry.path();
      const std::string name = fs::relative(dir, shared).string();
      for (const char* m : methods) {
        const std::string method = m;
        const std::string what = "shared/" + name;
        benchmark::RegisterBenchmark(("bgs/" + method + "/" + what).c_str(),
                                     [method, what, dir](benchmark::State& st) {
                                       static std::map<std::string, Sequence> cache;
                                       auto it = cache.find(dir.string());
                                       if (it == cache.end())
                                         it = cache.emplace(dir.string(), from_disk(dir)).first;
                                       run(st, method, what, it->second);
                                     })
            ->Unit(benchmark::kMillisecond);
      }
    }
  }
  return true;
}();

}  // namespace
