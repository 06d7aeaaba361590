#include <catch2/catch.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/common/joints.hpp"
#include "hullpose/common/log.hpp"

using namespace hullpose;

HULLPOSE_LOG_CATEGORY(TestCat, "testcat")

TEST_CASE("log levels are set at run time per category") {
  log::set_levels("testcat:warn");
  CHECK_FALSE(log_category_TestCat().enabled(log::Level::Info));
  CHECK(log_category_TestCat().enabled(log::Level::Error));
  log::set_levels("*:debug");
  CHECK(log_category_TestCat().enabled(log::Level::Debug));
  CHECK_THROWS_WITH(log::set_levels("testcat:loud"), Catch::Contains("'loud'"));
  CHECK_THROWS_WITH(log::set_levels("testcat"), Catch::Contains("name:level"));
  log::set_levels("*:info");
  HULLPOSE_LOG(TestCat, Info) << "a message with a number " << 42;
}

TEST_CASE("counters count by name") {
  Counters c;
  c.add("late");
  c.add("late", 2);
  c.add("duplicate");
  CHECK(c.get("late") == 3);
  CHECK(c.get("missing") == 0);
  CHECK(c.total() == 4);
  CHECK(c.snapshot().size() == 2);
}

TEST_CASE("joint model matches the thesis") {
  CHECK(kJointNames.size() == 25);
  CHECK(name(Joint::RToe) == "RToe");
  CHECK(joint_from_name("LKne") == Joint::LKne);
  CHECK_FALSE(joint_from_name("Nose").has_value());
  CHECK(mirror(Joint::LSho) == Joint::RSho);
  CHECK(mirror(Joint::RToe) == Joint::LToe);
  CHECK(mirror(Joint::LBack) == Joint::LBack);
  CHECK(mirror(Joint::Chest) == Joint::Chest);
  // Every joint but the root (Chest) is the child of exactly one bone; parents come first.
  std::array<int, kNumJoints> as_child{};
  std::array<bool, kNumJoints> reached{};
  reached[index(Joint::Chest)] = true;
  for (const Bone& b : kBones) {
    CHECK(reached[index(b.parent)]);
    reached[index(b.child)] = true;
    ++as_child[index(b.child)];
  }
  for (int j = 0; j < kNumJoints; ++j) CHECK(as_child[j] == (j == index(Joint::Chest) ? 0 : 1));
  // The vertical chain head-top -> ankle is 0.822 of the stature in Table 6.7; the hip bones'
  // drop and the ankle height make up the rest.
  double chain = 0;
  for (const Bone& b : kBones)
    if (b.name == "Head" || b.name == "Upper neck" || b.name == "Lower neck" ||
        b.name == "Thorax" || b.name == "Upper spine" || b.name == "Lower spine" ||
        (b.name == "Thigh" && b.child == Joint::LKne) ||
        (b.name == "Lower leg" && b.child == Joint::LAnk))
      chain += b.stature_ratio;
  CHECK(chain == Approx(0.822).margin(1e-9));
}

TEST_CASE("THROW_UNLESS carries its message") {
  CHECK_THROWS_WITH([] { HULLPOSE_THROW_UNLESS(1 == 2, "camera " << 3 << ": broken"); }(),
                    "camera 3: broken");
}

#include "hullpose/common/voxel_grid.hpp"

TEST_CASE("voxel grid fits the capture volume with cubic voxels") {
  const CaptureVolume vol{{-1000, -1000, 0}, {1000, 1000, 2200}};
  const VoxelGridSpec g = VoxelGridSpec::fit(vol, 128);
  CHECK(g.dims == Eigen::Vector3i(117, 117, 128));
  CHECK(g.voxel_mm == Approx(2200.0 / 128));
  CHECK(g.centre_mm({0, 0, 0}).z() == Approx(g.voxel_mm / 2));
  CHECK(g.index(1, 2, 3) == (3u * 117 + 2) * 117 + 1);
  CHECK(g.contains({116, 0, 127}));
  CHECK_FALSE(g.contains({117, 0, 0}));
  CHECK_THROWS_WITH(VoxelGridSpec::fit(vol, 3), Catch::Contains("resolution"));
}
