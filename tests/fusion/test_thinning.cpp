// CK3 / D6I1D property tests (notes §5): topology, crucial cliques, stability, symmetry, thread
// and order independence, canonical shapes, idempotence.
#include <catch2/catch.hpp>
#include <random>

#include "hullpose/thin/thinning.hpp"
#include "hullpose/thin/topology_stats.hpp"
#include "support/synthetic_scene.hpp"
#include "support/volumes.hpp"

using namespace hullpose;
using fusion::BitGrid;
using thin::CurveRule;
namespace ft = hullpose::fusion::testing;

namespace {

const CurveRule kAllRules[] = {CurveRule::kUltimate, CurveRule::kCk3, CurveRule::kIsthmus, CurveRule::kEndVoxel};

BitGrid thinned(const BitGrid& x, CurveRule rule, int threads = 1, BitGrid* k = nullptr, int max_iterations = 0) {
  thin::Ck3Thinner t({rule, thin::ZeroCliqueTest::kSpan3, threads, max_iterations});
  BitGrid y = x;
  t.thin(y, k);
  return y;
}

bool subset(const BitGrid& a, const BitGrid& b) {
  for (size_t i = 0; i < a.words().size(); ++i)
    if (a.words()[i] & ~b.words()[i]) return false;
  return true;
}

// Topology preserved, result inside X, stable with K carried over, first step hits every
// crucial clique (checked with the naive reference on small volumes only).
void check_thinning(const BitGrid& x, CurveRule rule, bool check_cliques) {
  INFO("rule " << thin::to_string(rule));
  BitGrid k;
  const BitGrid y = thinned(x, rule, 1, &k);
  CHECK(subset(y, x));
  CHECK(thin::topology_invariants(y) == thin::topology_invariants(x));
  // Stability: one more iteration with K carried over deletes nothing.
  BitGrid k2 = k;
  const BitGrid again = thinned(y, rule, 1, &k2, 1);
  CHECK(again == y);
  if (check_cliques) {
    const BitGrid step = thinned(x, rule, 1, nullptr, 1);
    CHECK(ft::crucial_cliques_missed(x, step) == 0);
  }
}

}  // namespace

TEST_CASE("run-based invariants equal the dense BFS / Khalimsky reference") {
  std::mt19937 rng(11);
  for (int i = 0; i < 12; ++i) {
    const BitGrid v = i < 6 ? ft::random_blobs(rng, 18, 6) : ft::random_noise(rng, {9, 8, 7}, 0.5, 1);
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
  for (int i = 0; i < 6; ++i) {
    const BitGrid x = ft::random_blobs(rng, 20, 8);
    for (CurveRule rule : kAllRules) check_thinning(x, rule, i < 2);
  }
}

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
        INFO("rule " << thin::to_string(rule) << " perm " << g.perm[0] << g.perm[1] << g.perm[2] << " flip "
                     << g.flip[0] << g.flip[1] << g.flip[2]);
        CHECK(thinned(ft::apply(g, x), rule) == ft::apply(g, y));
      }
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
      y.for_each([&](int vx, int vy, int) { CHECK(std::abs(std::hypot(vx - c, vy - c) - 10) <= tol); });
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
    if (r.ult >= 0) CHECK(thinned(r.shape, CurveRule::kUltimate).count() == static_cast<size_t>(r.ult));
    if (r.isth >= 0) CHECK(thinned(r.shape, CurveRule::kIsthmus).count() == static_cast<size_t>(r.isth));
    if (r.end >= 0) CHECK(thinned(r.shape, CurveRule::kEndVoxel).count() == static_cast<size_t>(r.end));
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

TEST_CASE("the antipodal 0-clique test of Pink/DGtal deletes the tripod, the span test keeps it (notes §2.5)") {
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

TEST_CASE("D6I1D preserves topology, is stable and keeps limbs") {
  std::mt19937 rng(17);
  std::vector<BitGrid> shapes = {ft::random_blobs(rng, 20, 8), ft::torus(8, 2.5, false), ft::trefoil_tube(3.2, 2.2),
                                 ft::hollow_ball(7, 2), ft::random_noise(rng, {10, 9, 8}, 0.5, 2)};
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
