// The pose stage does not allocate per frame at steady state: global operator new is counted
// while a sequence of frames is estimated a second time.
#include <catch2/catch.hpp>

#include "capsule_hull.hpp"
#include "hullpose/pose/hull_pose_estimator.hpp"
#include "hullpose/pose/pose_estimator.hpp"
#include "stick_figure.hpp"
#include "support/alloc_count.hpp"

using namespace hullpose;
using namespace hullpose::pose;
using namespace hullpose::pose::test;

TEST_CASE("no allocation per frame at steady state") {
  const VoxelGridSpec g = grid_2m(128);
  std::vector<std::vector<Eigen::Vector3i>> frames;
  Limbs walk = t_pose();
  walk.l_thigh = {0, 0.4, -1};
  walk.r_thigh = {0, -0.3, -1};
  walk.l_upper_arm = {0.3, -0.3, -1};
  for (int f = 0; f < 12; ++f) {
    auto voxels = rasterise(g, stick_figure(1750, f < 6 ? walk : t_pose(), {f * 4.0, 0, 0, 0}));
    add_spurs(g, voxels, 10, 4, static_cast<uint32_t>(f + 1));
    frames.push_back(std::move(voxels));
  }
  frames.push_back({});  // an empty frame on the way
  PoseEstimator estimator;
  for (const auto& f : frames) estimator.estimate(f, g);  // warm up: buffers grow to size
  const long before = hullpose::test::allocations();
  int valid = 0;
  for (const auto& f : frames) valid += estimator.estimate(f, g).valid;
  const long during = hullpose::test::allocations() - before;
  CHECK(during == 0);
  CHECK(valid >= 10);
}

TEST_CASE("no allocation per frame at steady state, tracking on the hull") {
  const VoxelGridSpec g = grid_2m(64);
  const BodyModel body = BodyModel::from_stature(1750);
  std::vector<std::vector<Eigen::Vector3i>> frames;
  std::vector<fusion::BitGrid> hulls(12);
  Limbs walk = t_pose();
  walk.l_thigh = {0, 0.4, -1};
  walk.r_thigh = {0, -0.3, -1};
  walk.l_upper_arm = {0.3, -0.3, -1};
  for (int f = 0; f < 12; ++f) {
    const JointPositions joints = stick_figure(1750, f < 6 ? walk : t_pose(), {f * 4.0, 0, 0, 0});
    frames.push_back(rasterise(g, joints));
    capsule_hull(g, joints, body, hulls[static_cast<size_t>(f)]);
  }
  HullPoseEstimator estimator;  // tracking: tree, bottom-up fit, surface, ICP, arbitration, filter
  auto run = [&] {
    int valid = 0;
    for (size_t f = 0; f < frames.size(); ++f)
      valid += estimator.estimate(frames[f], &hulls[f], g).valid;
    valid += estimator.estimate({}, nullptr, g).valid;  // a failed hull on the way
    return valid;
  };
  run();  // warm up
  const long before = hullpose::test::allocations();
  const int valid = run();
  const long during = hullpose::test::allocations() - before;
  CHECK(during == 0);
  CHECK(valid >= 10);
}
