// Notes §2.5 / §5.2: one thinning step on 10^5 random small windows must preserve b0, cavities
// and the Euler characteristic (0 failures; the antipodal 0-clique test fails here), and every
// crucial clique must keep a voxel (checked with the naive reference on a subset).
#include <catch2/catch.hpp>
#include <random>

#include "hullpose/thin/thinning.hpp"
#include "hullpose/thin/topology_stats.hpp"
#include "support/volumes.hpp"

using namespace hullpose;
namespace ft = hullpose::fusion::testing;

namespace {

struct FuzzResult {
  int topology_failures = 0, clique_failures = 0, cases = 0;
};

FuzzResult fuzz(thin::ZeroCliqueTest zero, int cases, int clique_checks, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> side(4, 6);
  std::uniform_real_distribution<double> density(0.3, 0.8);
  thin::Ck3Thinner thinner({thin::CurveRule::kUltimate, zero, 1, 1});
  thin::ComponentLabeller labeller;
  FuzzResult r;
  fusion::BitGrid y;
  for (int i = 0; i < cases; ++i) {
    // Density first: the order x86-64 GCC evaluated the arguments in (unspecified in C++).
    const double d = density(rng);
    const int sx = side(rng), sy = side(rng), sz = side(rng);
    const fusion::BitGrid x = ft::random_noise(rng, {sx, sy, sz}, d, 1);
    y = x;
    thinner.thin(y);
    if (labeller.invariants(y) != labeller.invariants(x)) ++r.topology_failures;
    if (i < clique_checks && ft::crucial_cliques_missed(x, y) != 0) ++r.clique_failures;
    ++r.cases;
  }
  return r;
}

}  // namespace

TEST_CASE("crucial-clique fuzz: 10^5 random windows, one step, 0 failures") {
  const FuzzResult r = fuzz(thin::ZeroCliqueTest::kSpan3, 100000, 3000, 2024);
  CHECK(r.cases == 100000);
  CHECK(r.topology_failures == 0);
  CHECK(r.clique_failures == 0);
}

TEST_CASE("the same fuzz catches the antipodal 0-clique test (the fuzz has teeth)") {
  const FuzzResult r = fuzz(thin::ZeroCliqueTest::kAntipodal, 40000, 0, 2024);
  CHECK(r.topology_failures > 0);
}
