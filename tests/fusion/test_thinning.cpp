// CK3 / D6I1D property tests (notes §5): topology, crucial cliques, stability, symmetry, thread
// and order independence, canonical shapes, idempotence.
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

TEST_CASE("run-based invariants equal the dense BFS / Khalimsky reference") {
  std::mt19937 rng(11);
  for (int i = 0; i < 12; ++i) {
    const BitGrid v =
        i < 6 ? ft::random_blobs(rng, 18, 6) : ft::random_noise(rng, {9, 8, 7}, 0.5, 1);
    const auto a = thin::topology_invariants(v);
    const auto r = ft::reference_invariants(v);
    CHECK(a.components == r.components);
    CHECK(a.cavities == r.cavities);
    CHECK(a.euler == r.euler);
  }
  const auto t = thin::topology_invariants(ft::torus(6, 2, false));
  CHECK(t.components == 1);
  CHECK(t.cavities == 0);
  CHECK(t.tunnels() == 1);
  const auto h = thin::topology_invariants(ft::hollow_ball(6, 2));
  CHECK(h.cavities == 1);
  CHECK(h.euler == 2);
}

TEST_CASE("thinning preserves topology and hits every crucial clique: random blobs") {
  std::mt19937 rng(3);
  for (int i = 0; i < 3; ++i) {
    const BitGrid x = ft::random_blobs(rng, 18, 7);
    for (CurveRule rule : kAllRules) check_thinning(x, rule, i < 1);
  }
}

TEST_CASE("a solid cylinder becomes its axis in the curve modes") {
  const BitGrid x = ft::cylinder_x(4, 21);
  const double c = (x.dims().y() - 1) / 2.0;
  for (CurveRule rule : {CurveRule::kCk3, CurveRule::kIsthmus, CurveRule::kEndVoxel}) {
    INFO("rule " << thin::to_string(rule));
    const BitGrid y = thinned(x, rule);
    int n = 0, min_x = 1 << 30, max_x = -1;
    y.for_each([&](int vx, int vy, int vz) {
      CHECK(std::abs(vy - c) <= 1.0);
      CHECK(std::abs(vz - c) <= 1.0);
      min_x = std::min(min_x, vx);
      max_x = std::max(max_x, vx);
      ++n;
    });
    CHECK(n >= 9);  // a segment of the axis, not a point
    CHECK(max_x - min_x + 1 >= 9);
  }
}

TEST_CASE("a torus becomes a closed ring") {
  for (bool even : {false, true}) {
    const BitGrid x = ft::torus(10, 3, even);
    const double c = even ? x.dims().x() / 2.0 - 0.5 : (x.dims().x() - 1) / 2.0;
    for (CurveRule rule : kAllRules) {
      INFO("rule " << thin::to_string(rule) << " even " << even);
      const BitGrid y = thinned(x, rule);
      const auto t = thin::topology_invariants(y);
      CHECK(t.components == 1);
      CHECK(t.tunnels() == 1);
      // The thesis rule keeps residual points of a still 3-thick ring on the even grid (2 voxels).
      const double tol = rule == CurveRule::kCk3 ? 2.0 : 1.0;
      y.for_each(
          [&](int vx, int vy, int) { CHECK(std::abs(std::hypot(vx - c, vy - c) - 10) <= tol); });
    }
  }
}

TEST_CASE("canonical shapes reproduce the table of notes §5.4") {
  struct Row {
    const char* name;
    BitGrid shape;
    int ult, isth, end;  // -1: not in the table
  };
  const Row rows[] = {
      {"cube 9", ft::box(9, 9, 9), 1, 1, 1},
      {"box 11x7x5", ft::box(11, 7, 5), 1, 3, 5},
      {"box 12x8x6", ft::box(12, 8, 6), 8, 16, 8},
      {"plate 11x7x1", ft::box(11, 7, 1), -1, 3, -1},
      {"ball R6 even", ft::ball(6, true), 8, 8, 8},
      {"cylinder r4 l21", ft::cylinder_x(4, 21), 1, 11, 13},
      {"cylinder r4 l20", ft::cylinder_x(4, 20), 2, 10, 12},
      {"cross 5x5", ft::cross_bars(5, 21), 1, 29, 33},
  };
  for (const Row& r : rows) {
    INFO(r.name);
    if (r.ult >= 0)
      CHECK(thinned(r.shape, CurveRule::kUltimate).count() == static_cast<size_t>(r.ult));
    if (r.isth >= 0)
      CHECK(thinned(r.shape, CurveRule::kIsthmus).count() == static_cast<size_t>(r.isth));
    if (r.end >= 0)
      CHECK(thinned(r.shape, CurveRule::kEndVoxel).count() == static_cast<size_t>(r.end));
  }
  // Hollow sphere: a closed 2-thick surface around the cavity in every mode, not thinned further.
  const BitGrid hollow = ft::hollow_ball(8, 2);
  for (CurveRule rule : kAllRules) {
    const BitGrid y = thinned(hollow, rule);
    CHECK(thin::topology_invariants(y).cavities == 1);
    CHECK(y.count() > 500);
  }
}

TEST_CASE("idempotent on its own output with K carried over") {
  std::mt19937 rng(13);
  const BitGrid x = ft::random_blobs(rng, 22, 7);
  for (CurveRule rule : kAllRules) {
    BitGrid k;
    const BitGrid y = thinned(x, rule, 1, &k);
    BitGrid k2 = k;
    CHECK(thinned(y, rule, 1, &k2) == y);
    CHECK(k2 == k);
  }
  // End-voxel and ultimate modes are fixed points even with an empty K (notes §5.3).
  for (CurveRule rule : {CurveRule::kUltimate, CurveRule::kEndVoxel}) {
    const BitGrid y = thinned(x, rule);
    CHECK(thinned(y, rule) == y);
  }
}

TEST_CASE(
    "the antipodal 0-clique test of Pink/DGtal deletes the tripod, the span test keeps it (notes "
    "§2.5)") {
  BitGrid tripod({6, 6, 6});
  tripod.set(2, 2, 2);
  tripod.set(3, 3, 2);
  tripod.set(2, 3, 3);
  thin::Ck3Thinner span({CurveRule::kUltimate, thin::ZeroCliqueTest::kSpan3, 1, 1});
  thin::Ck3Thinner anti({CurveRule::kUltimate, thin::ZeroCliqueTest::kAntipodal, 1, 1});
  BitGrid a = tripod, b = tripod;
  span.thin(a);
  anti.thin(b);
  CHECK(a.count() == 3);
  CHECK(b.count() == 0);
}

TEST_CASE(
    "small: the result does not depend on the thread count, and commutes with the cube "
    "symmetries") {
  std::mt19937 rng(29);
  const BitGrid blob = ft::random_blobs(rng, 14, 5);
  const BitGrid box = ft::box(7, 5, 4);
  for (CurveRule rule : {CurveRule::kCk3, CurveRule::kIsthmus}) {
    INFO("rule " << thin::to_string(rule));
    const BitGrid one = thinned(blob, rule, 1);
    CHECK(thinned(blob, rule, 2) == one);
    CHECK(thinned(blob, rule, 3) == one);
    const BitGrid y = thinned(box, rule);
    for (const auto& g : ft::all_isometries())
      CHECK(thinned(ft::apply(g, box), rule) == ft::apply(g, y));
  }
}
