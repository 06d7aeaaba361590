#pragma once
// Shared checks of the thinning tests (Catch2 assertions).
#include <catch2/catch.hpp>

#include "hullpose/thin/thinning.hpp"
#include "hullpose/thin/topology_stats.hpp"
#include "support/volumes.hpp"

namespace hullpose::fusion::testing {

inline const thin::CurveRule kAllRules[] = {thin::CurveRule::kUltimate, thin::CurveRule::kCk3,
                                            thin::CurveRule::kIsthmus, thin::CurveRule::kEndVoxel};

inline BitGrid thinned(const BitGrid& x, thin::CurveRule rule, int threads = 1,
                       BitGrid* k = nullptr, int max_iterations = 0) {
  thin::ThinOptions options{rule, thin::ZeroCliqueTest::kSpan3, threads, max_iterations};
  options.min_parallel_border = 0;  // run the parallel path even on small test volumes
  thin::Ck3Thinner t(options);
  BitGrid y = x;
  t.thin(y, k);
  return y;
}

inline bool subset(const BitGrid& a, const BitGrid& b) {
  for (size_t i = 0; i < a.words().size(); ++i)
    if (a.words()[i] & ~b.words()[i]) return false;
  return true;
}

// Topology preserved, result inside X, stable with K carried over, first step hits every
// crucial clique (checked with the naive reference on small volumes only).
inline void check_thinning(const BitGrid& x, thin::CurveRule rule, bool check_cliques) {
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
    CHECK(crucial_cliques_missed(x, step) == 0);
  }
}

}  // namespace hullpose::fusion::testing
