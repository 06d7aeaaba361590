// Carving at 128³ and 256³ equals the brute-force reference voxel for voxel (integration: the
// reference is slow in the Debug sanitizer build).
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "hullpose/carve/carver.hpp"
#include "support/carve_helpers.hpp"
#include "support/synthetic_scene.hpp"

using namespace hullpose;
using fusion::BitGrid;
namespace ft = hullpose::fusion::testing;
using ft::brute;
using ft::fast;

TEST_CASE("fast carving equals brute force at 64³ and 128³") {
  const Rig rig = ft::thesis_like_rig(320, 240);
  for (int res : {64, 128}) {
    for (int k : {0, 1}) {
      carve::Carver carver(rig, {res, k, 2});
      for (double phase : {0.1, 0.6}) {
        INFO("resolution " << res << " k " << k << " phase " << phase);
        const auto views =
            ft::render_views(rig, ft::human_capsules(phase, 3 * phase, {200 * phase, -100}));
        carve::CarveReport report;
        const BitGrid a = fast(carver, views, &report);
        CHECK(report.valid);
        CHECK(report.cameras_used == 8);
        CHECK(report.voxels == a.count());
        CHECK(a.count() > 1000);
        CHECK(a == brute(carver, views));
      }
    }
  }
}

TEST_CASE("fast carving equals brute force at 256³ (3 small cameras)") {
  const Rig rig = ft::thesis_like_rig(200, 150, 3);
  carve::Carver carver(rig, {256, 0, 2});
  const auto views = ft::render_views(rig, ft::human_capsules(0.35));
  const BitGrid a = fast(carver, views);
  CHECK(a.count() > 10000);
  CHECK(a == brute(carver, views));
}
