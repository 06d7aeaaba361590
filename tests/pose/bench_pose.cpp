// Pose stage per frame: tree + labels + SHAKE fit (goal: <= 1 ms median at 128^3; the thesis
// took 3.1 ms for the tree and 2.9 ms for SHAKE). Input: a walking stick figure's skeleton with
// spurious branches, as thinning leaves on a real hull.
#include <benchmark/benchmark.h>

#include "hullpose/pose/pose_estimator.hpp"
#include "stick_figure.hpp"

namespace {
using namespace hullpose;
using namespace hullpose::pose;
using namespace hullpose::pose::test;

std::vector<Eigen::Vector3i> walking_skeleton(const VoxelGridSpec& g) {
  Limbs walk = t_pose();
  walk.l_upper_arm = {0.2, 0.4, -1};
  walk.l_forearm = {0.1, 0.8, -0.6};
  walk.r_upper_arm = {-0.2, -0.4, -1};
  walk.r_forearm = {-0.1, 0.2, -1};
  walk.l_thigh = {0, 0.5, -1};
  walk.l_shin = {0, -0.1, -1};
  walk.r_thigh = {0, -0.3, -1};
  walk.r_shin = {0, -0.6, -1};
  auto voxels = rasterise(g, stick_figure(1750, walk, {35, 0, 0, 0}));
  add_spurs(g, voxels, 20, 5, 11);
  return voxels;
}

void tree_and_fit(benchmark::State& state) {
  const VoxelGridSpec g = grid_2m(static_cast<int>(state.range(0)));
  const auto voxels = walking_skeleton(g);
  PoseEstimator estimator;
  if (!estimator.estimate(voxels, g).valid) state.SkipWithError("fixture not valid");
  for (auto _ : state) benchmark::DoNotOptimize(estimator.estimate(voxels, g).joints_mm[0].x());
  state.counters["voxels"] = static_cast<double>(voxels.size());
}

void tree_only(benchmark::State& state) {
  const VoxelGridSpec g = grid_2m(static_cast<int>(state.range(0)));
  const auto voxels = walking_skeleton(g);
  PoseTreeBuilder builder;
  for (auto _ : state) benchmark::DoNotOptimize(builder.build(voxels, g, TemporalHint{}).valid);
}

void fit_only(benchmark::State& state) {
  const VoxelGridSpec g = grid_2m(static_cast<int>(state.range(0)));
  const auto voxels = walking_skeleton(g);
  PoseTreeBuilder builder;
  const LabelledTree& tree = builder.build(voxels, g, TemporalHint{});
  if (!tree.valid) state.SkipWithError("fixture not valid");
  ModelFitter fitter;
  const double stature = fitter.frame_stature(tree);
  for (auto _ : state) benchmark::DoNotOptimize(fitter.fit(tree, stature).joints[0].x());
  state.counters["shake_iterations"] = fitter.result().iterations;
}

BENCHMARK(tree_and_fit)->Name("pose/tree+fit")->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(tree_and_fit)->Name("pose/tree+fit")->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(tree_only)->Name("pose/tree")->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK(fit_only)->Name("pose/fit")->Arg(128)->Unit(benchmark::kMillisecond);

}  // namespace
