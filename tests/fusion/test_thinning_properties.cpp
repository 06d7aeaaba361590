// CK3 / D6I1D property tests on larger volumes (notes §5): tori, knotted tubes, hollow balls,
// human hulls, thread-count independence, the 48 cube symmetries, D6I1D. Label integration:
// seconds in a release build, minutes under the Debug sanitizer build.
#include <catch2/catch.hpp>
#include <random>

#include "hullpose/thin/thinning.hpp"
#include "hullpose/thin/topology_stats.hpp"
#include "support/synthetic_scene.hpp"
#include "support/thin_checks.hpp"
#include "support/volumes.hpp"

using namespace hullpose;
using fusion::BitGrid;
using thin::CurveRule;
namespace ft = hullpose::fusion::testing;
using ft::check_thinning;
using ft::kAllRules;
using ft::subset;
using ft::thinned;

TEST_CASE("thinning preserves topology: random noise (many components, cavities and tunnels)") {
  std::mt19937 rng(5);
  for (int i = 0; i < 6; ++i) {
    const BitGrid x = ft::random_noise(rng, {10, 9, 8}, 0.35 + 0.08 * i, 2);
    for (CurveRule rule : kAllRules) check_thinning(x, rule, true);
  }
}

TEST_CASE("tori, knotted tubes and hollow balls") {
  for (CurveRule rule : kAllRules) {
    check_thinning(ft::torus(8, 2.5, false), rule, false);
    check_thinning(ft::torus(7, 3, true), rule, false);
    check_thinning(ft::trefoil_tube(3.2, 2.2), rule, false);
    check_thinning(ft::hollow_ball(7, 2), rule, false);
  }
}

TEST_CASE("synthetic human hulls") {
  const Rig rig = ft::thesis_like_rig();
  const VoxelGridSpec grid = VoxelGridSpec::fit(rig.volume, 64);
  for (double phase : {0.0, 0.3, 0.7}) {
    const BitGrid x = ft::voxelise(grid, ft::human_capsules(phase, phase * 2));
    REQUIRE(thin::topology_invariants(x).components == 1);
    for (CurveRule rule : kAllRules) check_thinning(x, rule, false);
    // A curve skeleton is a small fraction of the body (at 64³ limbs are only 2-4 voxels thick,
    // and symmetric thinning leaves even widths 2 thick), about as large as the 1D-isthmus one.
    const BitGrid y = thinned(x, CurveRule::kCk3);
    CHECK(y.count() * 3 < x.count());
    CHECK(y.count() * 2 < thinned(x, CurveRule::kIsthmus).count() * 3);
  }
}

TEST_CASE("the result does not depend on the thread count") {
  const Rig rig = ft::thesis_like_rig();
  const VoxelGridSpec grid = VoxelGridSpec::fit(rig.volume, 64);
  const BitGrid x = ft::voxelise(grid, ft::human_capsules(0.45, 0.7, {150, -80}));
  std::mt19937 rng(9);
  const BitGrid blobs = ft::random_blobs(rng, 24, 10);
  for (CurveRule rule : kAllRules)
    for (const BitGrid* v : {&x, &blobs}) {
      const BitGrid one = thinned(*v, rule, 1);
      CHECK(thinned(*v, rule, 2) == one);
      CHECK(thinned(*v, rule, 3) == one);
    }
}

TEST_CASE("thinning commutes with the 48 symmetries of the cube") {
  std::mt19937 rng(21);
  const BitGrid shapes[] = {ft::random_blobs(rng, 16, 6), ft::box(11, 7, 5), ft::cross_bars(5, 15)};
  const auto isometries = ft::all_isometries();
  REQUIRE(isometries.size() == 48);
  for (CurveRule rule : kAllRules)
    for (const BitGrid& x : shapes) {
      const BitGrid y = thinned(x, rule);
      for (const auto& g : isometries) {
        INFO("rule " << thin::to_string(rule) << " perm " << g.perm[0] << g.perm[1] << g.perm[2]
                     << " flip " << g.flip[0] << g.flip[1] << g.flip[2]);
        CHECK(thinned(ft::apply(g, x), rule) == ft::apply(g, y));
      }
    }
}

TEST_CASE("D6I1D preserves topology, is stable and keeps limbs") {
  std::mt19937 rng(17);
  std::vector<BitGrid> shapes = {ft::random_blobs(rng, 20, 8), ft::torus(8, 2.5, false),
                                 ft::trefoil_tube(3.2, 2.2), ft::hollow_ball(7, 2),
                                 ft::random_noise(rng, {10, 9, 8}, 0.5, 2)};
  const Rig rig = ft::thesis_like_rig();
  shapes.push_back(ft::voxelise(VoxelGridSpec::fit(rig.volume, 64), ft::human_capsules(0.2)));
  thin::D6i1dThinner d6;
  for (const BitGrid& x : shapes) {
    BitGrid y = x, k;
    d6.thin(y, &k);
    CHECK(subset(y, x));
    CHECK(thin::topology_invariants(y) == thin::topology_invariants(x));
    BitGrid again = y;
    thin::D6i1dThinner({1}).thin(again, &k);
    CHECK(again == y);
  }
  // Cylinder to an axis segment.
  BitGrid cyl = ft::cylinder_x(4, 21);
  d6.thin(cyl);
  const double c = (cyl.dims().y() - 1) / 2.0;
  int n = 0;
  cyl.for_each([&](int, int vy, int vz) {
    CHECK(std::abs(vy - c) <= 1.0);
    CHECK(std::abs(vz - c) <= 1.0);
    ++n;
  });
  CHECK(n >= 5);
}
