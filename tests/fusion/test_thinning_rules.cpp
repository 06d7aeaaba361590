// The CPU thinner (src/ck3.cpp: neighbour flags gathered word-wise from bit planes) against a
// plain driver of the shared per-voxel rules (ck3_rules.hpp, which the CUDA backend runs
// verbatim): every voxel of the volume visited in every pass, neighbours' flags read one by one
// from a byte array. Equal results on every rule, 0-clique test and volume, including real
// crane hulls (rough surfaces), keep the two backends' skeletons identical.
#include <catch2/catch.hpp>
#include <random>

#include "hullpose/carve/carver.hpp"
#include "hullpose/fusion/hull_cleanup.hpp"
#include "hullpose/thin/ck3_rules.hpp"
#include "hullpose/thin/thinning.hpp"
#include "support/crane_scene.hpp"
#include "support/thin_checks.hpp"
#include "support/volumes.hpp"

using namespace hullpose;
namespace ft = hullpose::fusion::testing;
using namespace hullpose::thin::ck3;

namespace {

// A dense volume with 2 voxels of background padding, byte flags per voxel.
struct DenseView {
  int nx, ny, nz;
  std::vector<uint8_t> object, flag;
  int off[27] = {}, faces[6] = {};
  DenseView(const fusion::BitGrid& g)
      : nx(g.dims().x() + 4),
        ny(g.dims().y() + 4),
        nz(g.dims().z() + 4),
        object(static_cast<size_t>(nx) * ny * nz, 0),
        flag(object.size(), 0) {
    g.for_each([&](int x, int y, int z) { object[index(x + 2, y + 2, z + 2)] = 1; });
    for (int b = 0; b < 27; ++b)
      off[b] = (b % 3 - 1) + (b / 3 % 3 - 1) * nx + (b / 9 - 1) * nx * ny;
    const int d6[6] = {-nx * ny, nx * ny, -nx, nx, -1, 1};  // -z, +z, -y, +y, -x, +x
    for (int d = 0; d < 6; ++d) faces[d] = d6[d];
  }
  uint32_t index(int x, int y, int z) const { return static_cast<uint32_t>((z * ny + y) * nx + x); }
  uint8_t flags(uint32_t i) const { return flag[i]; }
  bool get(uint32_t i) const { return object[i] != 0; }
  int off27(int b) const { return off[b]; }
  int face(int d) const { return faces[d]; }
  uint32_t code(uint32_t i) const {
    uint32_t c = 0;
    for (int b = 0; b < 27; ++b)
      c |= static_cast<uint32_t>(object[i + static_cast<uint32_t>(off[b])]) << b;
    return c;
  }
};

// Notes §2.6 straight: border = object voxels with a background face neighbour or already in the
// border, not in K; passes over all of them in turn; stop when nothing is deleted and K did not
// grow.
fusion::BitGrid reference_thin(const fusion::BitGrid& x, thin::CurveRule rule,
                               thin::ZeroCliqueTest zero) {
  DenseView v(x);
  const RuleTables& t = host_rule_tables();
  std::vector<uint32_t> border;
  std::vector<uint32_t> codes;
  std::vector<uint8_t> in_border(v.object.size(), 0), in_k(v.object.size(), 0);
  for (;;) {
    border.clear();
    for (uint32_t i = 0; i < v.object.size(); ++i) {
      if (!v.object[i] || in_k[i]) continue;
      bool exposed = in_border[i] != 0;
      for (int d = 0; d < 6 && !exposed; ++d)
        exposed = !v.object[i + static_cast<uint32_t>(v.faces[d])];
      if (exposed) border.push_back(i);
    }
    codes.resize(border.size());
    for (size_t k = 0; k < border.size(); ++k) codes[k] = v.code(border[k]);
    auto pass = [&](auto&& fn) {
      std::vector<uint8_t> next(border.size());
      for (size_t k = 0; k < border.size(); ++k)
        next[k] = fn(border[k], codes[k], v.flag[border[k]]);
      for (size_t k = 0; k < border.size(); ++k) v.flag[border[k]] = next[k];
    };
    pass([&](uint32_t, uint32_t c, uint8_t) { return classify(t, rule, c); });
    if (rule == thin::CurveRule::kCk3) {
      pass([&](uint32_t i, uint32_t c, uint8_t f) { return ck3_surface(v, t, i, c, f); });
      pass([&](uint32_t i, uint32_t c, uint8_t f) { return ck3_candidate(v, t, i, c, f); });
    } else if (rule == thin::CurveRule::kIsthmus) {
      pass([&](uint32_t i, uint32_t c, uint8_t f) { return isthmus_pairs(v, t, i, c, f); });
      pass([&](uint32_t i, uint32_t c, uint8_t f) { return isthmus_edges(v, t, i, c, f); });
      pass([&](uint32_t, uint32_t, uint8_t f) { return isthmus_settle(f); });
    }
    pass([&](uint32_t i, uint32_t c, uint8_t f) { return level2(v, t, i, c, f); });
    pass([&](uint32_t i, uint32_t c, uint8_t f) { return level1(v, t, i, c, f); });
    std::vector<uint32_t> deleted;
    for (size_t k = 0; k < border.size(); ++k)
      if (level0_deletes(v, t, border[k], codes[k], v.flag[border[k]], zero))
        deleted.push_back(border[k]);
    size_t grown = 0;
    for (uint32_t i : border) {
      if (v.flag[i] & kK) {
        in_k[i] = 1;
        ++grown;
      }
      in_border[i] = 1;
      v.flag[i] = 0;
    }
    for (uint32_t i : deleted) v.object[i] = 0;
    if (deleted.empty() && grown == 0) break;
  }
  fusion::BitGrid out(x.dims());
  x.for_each([&](int a, int b, int c) {
    if (v.object[v.index(a + 2, b + 2, c + 2)]) out.set(a, b, c);
  });
  return out;
}

void check_equal(const fusion::BitGrid& x, const char* what) {
  for (thin::CurveRule rule : ft::kAllRules)
    for (thin::ZeroCliqueTest zero :
         {thin::ZeroCliqueTest::kSpan3, thin::ZeroCliqueTest::kAntipodal}) {
      INFO(what << ", rule " << thin::to_string(rule) << ", antipodal "
                << (zero == thin::ZeroCliqueTest::kAntipodal));
      const fusion::BitGrid want = reference_thin(x, rule, zero);
      for (int threads : {1, 3}) {
        thin::ThinOptions o{rule, zero, threads, 0};
        o.min_parallel_border = 0;
        thin::Ck3Thinner thinner(o);
        fusion::BitGrid got = x;
        thinner.thin(got);
        INFO("threads " << threads);
        CHECK(got == want);
      }
    }
}

}  // namespace

TEST_CASE("CPU thinner equals the shared rules on shapes and noise", "[thin]") {
  check_equal(ft::ball(6.5, false), "ball");
  check_equal(ft::torus(7, 2.5, true), "torus");
  check_equal(ft::cross_bars(3, 15), "cross bars");
  check_equal(ft::hollow_ball(7, 2), "hollow ball");
  std::mt19937 rng(15);
  for (int i = 0; i < 6; ++i) check_equal(ft::random_blobs(rng, 20, 5), "blobs");
  for (int i = 0; i < 6; ++i) check_equal(ft::random_noise(rng, {14, 12, 10}, 0.55, 2), "noise");
}

TEST_CASE("CPU thinner equals the shared rules on real crane hulls", "[thin][real]") {
  ft::CraneFrames crane = ft::load_crane(2);
  carve::Carver carver(crane.rig, carve::CarveOptions{64, 0, 1});
  fusion::HullCleanup cleanup;
  for (const auto& views : crane.views) {
    fusion::BitGrid hull;
    carve::CarveReport report;
    fusion::HullStats stats;
    carver.carve(views, hull, report);
    cleanup.apply(hull, stats);
    REQUIRE(hull.count() > 1000);
    check_equal(hull, "crane");
  }
}
