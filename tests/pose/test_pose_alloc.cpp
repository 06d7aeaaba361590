// The pose stage does not allocate per frame at steady state: global operator new is counted
// while a sequence of frames is estimated a second time.
// The replaced operator new/delete pair malloc and free on purpose; GCC's mismatch check sees
// std::free of an operator new pointer once inlining crosses the replacement.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <new>

#include "capsule_hull.hpp"
#include "hullpose/pose/hull_pose_estimator.hpp"
#include "hullpose/pose/pose_estimator.hpp"
#include "stick_figure.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return operator new(n);
}
// The nothrow forms too (Catch uses them): otherwise they come from the runtime while their
// delete comes from here, which ASan rightly reports as an alloc-dealloc mismatch.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& tag) noexcept {
  return operator new(n, tag);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

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
  const long before = g_allocations.load();
  int valid = 0;
  for (const auto& f : frames) valid += estimator.estimate(f, g).valid;
  const long during = g_allocations.load() - before;
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
  const long before = g_allocations.load();
  const int valid = run();
  const long during = g_allocations.load() - before;
  CHECK(during == 0);
  CHECK(valid >= 10);
}
