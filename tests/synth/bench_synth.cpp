// Render speed of hullpose-synth: one frame of CMU 55_01 for the 8 thesis cameras at 800x600
// (the target: 1,000 such frames in under 2 minutes on 2 cores, i.e. < 240 ms of
// single-core time per frame). Runs single-threaded; the dataset writer spreads cameras over cores.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hullpose/synth/rig_gen.hpp"
#include "hullpose/synth/scene.hpp"

using namespace hullpose;
using namespace hullpose::synth;

namespace {

struct Fixture {
  Rig rig = make_ring_rig({});
  std::unique_ptr<Motion> motion =
      load_bvh_motion(std::filesystem::path(HULLPOSE_SHARED_DIR) / "data/mocap/55_01.bvh", {});
  BodyShape body;
  std::vector<ViewRenderer> views;
  Fixture() {
    body.stature_mm = motion->stature_mm();
    for (const auto& c : rig.cameras) views.emplace_back(c);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void masks(benchmark::State& state, bool encode) {
  cv::setNumThreads(1);
  Fixture& fx = fixture();
  const int frames = fx.motion->frame_count(30);
  JointPositions q;
  std::vector<Primitive> prims;
  cv::Mat mask;
  std::vector<uchar> png;
  const std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                   cv::IMWRITE_PNG_STRATEGY_RLE};
  int f = 0;
  for (auto _ : state) {
    fx.motion->sample((f++ % frames) / 30.0, q);
    pose_avatar(fx.body, q, prims);
    for (auto& view : fx.views) {
      view.render_mask(prims, mask);
      if (encode) cv::imencode(".png", mask, png, params);
    }
    benchmark::DoNotOptimize(mask.data);
  }
  state.counters["cameras"] = static_cast<double>(fx.views.size());
}

void BM_synth_masks_8cams(benchmark::State& state) {
  masks(state, false);
}
void BM_synth_masks_png_8cams(benchmark::State& state) {
  masks(state, true);
}

void BM_synth_rgb_8cams(benchmark::State& state) {
  cv::setNumThreads(1);
  Fixture& fx = fixture();
  static const Scene scene(SceneOptions{}, 1);
  static std::vector<std::unique_ptr<CameraRenderer>> cams;
  if (cams.empty())
    for (const auto& c : fx.rig.cameras)
      cams.push_back(std::make_unique<CameraRenderer>(*fx.motion, fx.body, c, scene, 30));
  const int frames = fx.motion->frame_count(30);
  JointPositions q;
  std::vector<Primitive> prims;
  cv::Mat atlas, bgr, mask;
  int f = 0;
  for (auto _ : state) {
    const int frame = f++ % frames;
    fx.motion->sample(frame / 30.0, q);
    pose_avatar(fx.body, q, prims);
    scene.shadows(prims, atlas);
    for (auto& cam : cams) cam->render_posed(frame, frame / 30.0, prims, atlas, bgr, mask);
    benchmark::DoNotOptimize(bgr.data);
  }
}

}  // namespace

BENCHMARK(BM_synth_masks_8cams)->Unit(benchmark::kMillisecond)->MinTime(2);
BENCHMARK(BM_synth_masks_png_8cams)->Unit(benchmark::kMillisecond)->MinTime(2);
BENCHMARK(BM_synth_rgb_8cams)->Unit(benchmark::kMillisecond)->MinTime(2);
