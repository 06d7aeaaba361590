#include <catch2/catch.hpp>
#include <filesystem>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/rig_gen.hpp"

using namespace hullpose;
using namespace hullpose::synth;
namespace fs = std::filesystem;

TEST_CASE("thesis8: 7 ring cameras + 1 ceiling camera at 800x600, all seeing the whole volume") {
  const Rig rig = rig_from_name_or_file("thesis8");
  REQUIRE(rig.cameras.size() == 8);
  CHECK(rig.cameras[7].name == "ceiling");
  for (const auto& c : rig.cameras) {
    INFO("camera " << c.id);
    CHECK(c.width == 800);
    CHECK(c.height == 600);
    // Every corner of the capture volume projects inside the image.
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d corner((k & 1) ? rig.volume.max_mm.x() : rig.volume.min_mm.x(),
                                   (k & 2) ? rig.volume.max_mm.y() : rig.volume.min_mm.y(),
                                   (k & 4) ? rig.volume.max_mm.z() : rig.volume.min_mm.z());
      const auto px = c.project(corner);
      REQUIRE(px);
      CHECK(px->x() > 0);
      CHECK(px->x() < c.width - 1);
      CHECK(px->y() > 0);
      CHECK(px->y() < c.height - 1);
    }
    // The volume centre is near the image centre.
    const auto centre = c.project(Eigen::Vector3d(0, 0, c.name == "ceiling" ? 0 : 1100));
    REQUIRE(centre);
    CHECK((*centre - Eigen::Vector2d(c.cx, c.cy)).norm() < 1);
  }
  // The ceiling camera sees +x to the right... of something; upright ring cameras see z up.
  const auto& cam0 = rig.cameras[0];
  CHECK(cam0.project({0, 0, 2000})->y() < cam0.project({0, 0, 100})->y());
}

TEST_CASE("a generated rig round-trips through the rig file; tilt and bad specs") {
  RingRigSpec spec;
  spec.ring_cameras = 5;
  spec.ceiling = false;
  spec.tilt_deg = 10;
  spec.k1 = -0.05;
  const Rig rig = make_ring_rig(spec);
  CHECK(rig.cameras.size() == 5);
  const fs::path file =
      fs::temp_directory_path() / ("hullpose-rig-gen-" + std::to_string(::getpid()) + ".yaml");
  save_rig(rig, file);
  CHECK(rig_from_name_or_file(file.string()) == rig);
  fs::remove(file);
  // A 10 degree tilt: the optical axis points 10 degrees below the horizon.
  const Eigen::Vector3d axis = rig.cameras[0].R.row(2).transpose();
  CHECK(std::asin(-axis.z()) * 180 / M_PI == Approx(10).margin(1e-9));
  spec.radius_mm = 1000;
  CHECK_THROWS_AS(make_ring_rig(spec), hullpose::Error);
  // The same ring from a command-line spec.
  const Rig parsed = rig_from_name_or_file("ring:cameras=5,ceiling=0,tilt=10,k1=-0.05");
  REQUIRE(parsed.cameras.size() == 5);
  CHECK(parsed.cameras[3] == rig.cameras[3]);
  CHECK_THROWS_WITH(rig_from_name_or_file("ring:cameras=5,zoom=2"),
                    Catch::Matchers::Contains("unknown key 'zoom'"));
}
