// The fusion core facade: silhouettes in, cleaned hull and skeleton out; clean-up; no
// allocation per frame at steady state.
#include <catch2/catch.hpp>

#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/thin/topology_stats.hpp"
#include "support/alloc_count.hpp"
#include "support/synthetic_scene.hpp"
#include "support/test_sizes.hpp"
#include "support/volumes.hpp"

using namespace hullpose;
using fusion::BitGrid;
namespace ft = hullpose::fusion::testing;

TEST_CASE("silhouettes of one instant in, hull and skeleton out") {
  const Rig rig = ft::thesis_like_rig(320, 240);
  Counters counters;
  for (auto sk : {fusion::Skeletoniser::kCk3, fusion::Skeletoniser::kD6i1d}) {
    fusion::FusionOptions opt;
    opt.resolution = ft::kUnitResolution;
    opt.skeletoniser = sk;
    fusion::FusionCore core(rig, opt, &counters);
    const auto views = ft::render_views(rig, ft::human_capsules(0.3));
    const fusion::FusionResult& r = core.process(views);
    REQUIRE(r.valid);
    CHECK(r.grid == core.grid());
    CHECK(r.hull_stats.voxels == r.hull.count());
    CHECK(r.hull_stats.components_kept == 1);
    CHECK(thin::topology_invariants(r.hull).components == 1);
    CHECK(r.skeleton_voxels.size() == r.skeleton.count());
    CHECK(r.thin.initial_voxels == r.hull.count());
    CHECK(r.thin.final_voxels == r.skeleton.count());
    CHECK(r.skeleton_voxels.size() > (ft::kSanitizerBuild ? 8u : 20u));
    for (const auto& v : r.skeleton_voxels) CHECK(r.hull.get(v.x(), v.y(), v.z()));
    CHECK(thin::topology_invariants(r.skeleton) == thin::topology_invariants(r.hull));
    CHECK(r.timings.total_ms >= r.timings.thin_ms);
    const BitGrid first = r.skeleton;
    core.process(views);
    CHECK(r.skeleton == first);
  }
}

TEST_CASE("too few views and an empty scene are counted, not fused") {
  const Rig rig = ft::thesis_like_rig(160, 120);
  Counters counters;
  fusion::FusionOptions opt;
  opt.resolution = ft::kUnitResolution;
  fusion::FusionCore core(rig, opt, &counters);
  std::vector<cv::Mat> views(8);
  const auto& r = core.process(views);
  CHECK_FALSE(r.valid);
  CHECK(r.failure == fusion::FusionFailure::kTooFewViews);
  CHECK(counters.get("fusion.too_few_views") == 1);
  CHECK(counters.get("fusion.camera_missing") == 8);
  for (auto& v : views) v = cv::Mat::zeros(120, 160, CV_8UC1);
  core.process(views);
  CHECK(r.failure == fusion::FusionFailure::kEmptyHull);
  CHECK(counters.get("fusion.empty_hull") == 1);
}

TEST_CASE("clean-up keeps the largest component (or all above a size) and fills small cavities") {
  BitGrid v = ft::hollow_ball(6, 3);  // one cavity
  const Eigen::Vector3i d = v.dims();
  v.set(0, 0, 0);                                              // a 1-voxel speck
  for (int x = 0; x < 4; ++x) v.set(x, d.y() - 1, d.z() - 1);  // a 4-voxel speck
  const size_t n = v.count();
  {
    BitGrid a = v;
    fusion::HullStats s;
    fusion::HullCleanup({0, 1000}).apply(a, s);
    CHECK(s.components == 3);
    CHECK(s.components_kept == 1);
    CHECK(s.voxels_dropped == 5);
    CHECK(s.cavities_filled == 1);
    CHECK(thin::topology_invariants(a).cavities == 0);
    CHECK(s.voxels == a.count());
    CHECK(s.voxels > n - 5);
  }
  {
    BitGrid a = v;
    fusion::HullStats s;
    fusion::HullCleanup({3, 0}).apply(a, s);
    CHECK(s.components_kept == 2);
    CHECK(s.voxels_dropped == 1);
    CHECK(s.cavities_filled == 0);
    CHECK(thin::topology_invariants(a).cavities == 1);
  }
}

TEST_CASE("no allocation per frame at steady state") {
  const Rig rig = ft::thesis_like_rig(320, 240);
  fusion::FusionOptions opt;
  opt.resolution = ft::kUnitResolution;
  fusion::FusionCore core(rig, opt);
  const auto a = ft::render_views(rig, ft::human_capsules(0.2));
  const auto b = ft::render_views(rig, ft::human_capsules(0.7, 1.0));
  for (int i = 0; i < 3; ++i) {
    core.process(a);
    core.process(b);
  }
  const long before = hullpose::test::allocations();
  core.process(a);
  core.process(b);
  CHECK(hullpose::test::allocations() - before == 0);
}
