// FootFacing on the hulls of standing stick figures (capsule_hull.hpp): the toes reach forward
// from the legs, whichever way the subject faces and at either voxel size; without feet the
// hull says nothing, and voxels too coarse to resolve a toe say nothing either.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "capsule_hull.hpp"
#include "hullpose/pose/foot_facing.hpp"

using namespace hullpose;
using namespace hullpose::pose;
using namespace hullpose::pose::test;

namespace {
constexpr double kStature = 1750;

// Standing, arms hanging at the sides: the pose a tree cannot read.
Limbs standing() {
  Limbs l;
  l.l_upper_arm = l.l_forearm = {0.15, 0, -1};
  l.r_upper_arm = l.r_forearm = {-0.15, 0, -1};
  l.l_thigh = l.l_shin = {0.03, 0, -1};
  l.r_thigh = l.r_shin = {-0.03, 0, -1};
  return l;
}

// Angle (degrees) between a horizontal direction and the front of a figure at `yaw_deg` (the
// stick figure faces +y at yaw 0).
double off_front(const Eigen::Vector2d& facing, double yaw_deg) {
  const double yaw = (yaw_deg + 90) * std::numbers::pi / 180;
  const double c = facing.normalized().dot(Eigen::Vector2d(std::cos(yaw), std::sin(yaw)));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / std::numbers::pi;
}
}  // namespace

TEST_CASE("the feet say which way a standing subject faces") {
  const BodyModel body = BodyModel::from_stature(kStature);
  FootFacing feet;
  fusion::BitGrid hull;
  for (int res : {64, 128}) {
    const VoxelGridSpec g = grid_2m(res);
    for (double yaw : {0.0, 75.0, 180.0, 250.0}) {
      INFO(res << "^3, facing " << yaw << " deg");
      const JointPositions truth = stick_figure(kStature, standing(), {yaw, 0, 100, -50});
      capsule_hull(g, truth, body, hull);
      Eigen::Vector2d facing(0, 0);
      REQUIRE(feet.measure(hull, g, kStature, facing));
      CHECK(off_front(facing, yaw) < 20);
      // One foot raised off the floor: the other still tells.
      Limbs one_up = standing();
      one_up.r_thigh = {-0.03, 0.5, -1};
      capsule_hull(g, stick_figure(kStature, one_up, {yaw, 0, 100, -50}), body, hull);
      REQUIRE(feet.measure(hull, g, kStature, facing));
      CHECK(off_front(facing, yaw) < 30);
    }
  }
}

TEST_CASE(
    "without feet in the hull, without a hull, or with voxels too coarse, the facing is not "
    "known") {
  const BodyModel body = BodyModel::from_stature(kStature);
  const VoxelGridSpec g = grid_2m(64);
  FootFacing feet;
  fusion::BitGrid hull;
  Eigen::Vector2d facing(0, 0);
  // Feet and toes left out: the shins end in round caps, the same all round.
  capsule_hull(g, stick_figure(kStature, standing()), body, hull, {20, 21, 22, 23});
  CHECK_FALSE(feet.measure(hull, g, kStature, facing));
  hull.reset(g.dims);
  CHECK_FALSE(feet.measure(hull, g, kStature, facing));
  // 62 mm voxels (0.036 statures): the feet are there, but a toe is one voxel high.
  const VoxelGridSpec coarse = grid_2m(32);
  capsule_hull(coarse, stick_figure(kStature, standing()), body, hull);
  CHECK_FALSE(feet.measure(hull, coarse, kStature, facing));
}
