// The one-frame-lag smoother of the published pose (lag_smoother.hpp): what it publishes for
// which frame, what it smooths and what it leaves as fitted.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "hullpose/common/check.hpp"
#include "hullpose/pose/body_model.hpp"
#include "hullpose/pose/lag_smoother.hpp"

using namespace hullpose;
using namespace hullpose::pose;

namespace {
constexpr double kStature = 1750;

// Table 6.7's body standing at `xy` (laid out once), its right arm raised `arm_rad` from hanging,
// about the shoulder. Laid out once on purpose: built with two standing_pose() calls per body, this
// helper returned collapsed poses in about half the runs of the ASan + UBSan build (-O1
// -march=native) when started by ctest, never in the release build (docs/perf-log.md, session 28).
JointPositions body(const Eigen::Vector2d& xy, double arm_rad = kHangingArmRad) {
  static const JointPositions base =
      standing_pose(BodyModel::from_stature(kStature), Eigen::Vector2d::Zero(), 0);
  JointPositions p = base;
  const Eigen::Vector3d shoulder = base[index(Joint::RSho)];
  const Eigen::AngleAxisd raise(arm_rad - kHangingArmRad, Eigen::Vector3d::UnitX());
  for (Joint j : {Joint::RElb, Joint::RHand, Joint::RFTip})
    p[index(j)] = shoulder + raise * (base[index(j)] - shoulder);
  for (Eigen::Vector3d& q : p) q += Eigen::Vector3d(xy.x(), xy.y(), 0);
  return p;
}

double max_distance(const JointPositions& a, const JointPositions& b) {
  double d = 0;
  for (int j = 0; j < kNumJoints; ++j) d = std::max(d, (a[j] - b[j]).norm());
  return d;
}
}  // namespace

TEST_CASE("lag smoother: each frame comes out one push later, in order; the last on release") {
  LagSmoother lag;
  CHECK(lag.push(body({0, 0}), true, true) == nullptr);
  CHECK(lag.holding());
  for (int n = 1; n < 5; ++n) {
    const JointPositions* out = lag.push(body({10.0 * n, 0}), true, true);
    REQUIRE(out != nullptr);
    // A body moving at constant velocity is its own centred mean: frame n - 1 exactly.
    CHECK(max_distance(*out, body({10.0 * (n - 1), 0})) < 1e-9);
  }
  const JointPositions* last = lag.release();
  REQUIRE(last != nullptr);
  CHECK(max_distance(*last, body({40, 0})) < 1e-9);
  CHECK_FALSE(lag.holding());
  CHECK(lag.release() == nullptr);
}

TEST_CASE(
    "lag smoother: a still pose's frame-to-frame noise is smoothed, its bones keep their lengths") {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 5);
  const JointPositions still = body({0, 0});
  const BodyModel model = BodyModel::from_stature(kStature);
  // As the stage publishes them: every frame with the model's bone lengths.
  std::vector<JointPositions> fitted(40, still);
  for (auto& p : fitted) {
    for (auto& j : p) j += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    impose_bone_lengths(p, model.length_mm);
  }
  LagSmoother lag;
  double fitted_sq = 0, published_sq = 0;
  int n = 0;
  for (size_t f = 0; f < fitted.size(); ++f) {
    const JointPositions* out = lag.push(fitted[f], true, true);
    if (out == nullptr || f < 2) continue;  // frame f - 1 has both neighbours from f = 2 on
    const JointPositions& own = fitted[f - 1];
    for (int b = 0; b < kNumBones; ++b) {
      const auto len = [&](const JointPositions& p) {
        return (p[index(kBones[b].child)] - p[index(kBones[b].parent)]).norm();
      };
      CHECK(len(*out) == Approx(len(own)).margin(1e-6));
    }
    for (int j = 0; j < kNumJoints; ++j) {
      fitted_sq += (own[j] - still[j]).squaredNorm();
      published_sq += ((*out)[j] - still[j]).squaredNorm();
    }
    ++n;
  }
  REQUIRE(n == 38);
  // Independent noise through weights 1/4, 1/2, 1/4 keeps 3/8 of its variance (0.61 of its
  // RMS), a little more once the bones get their lengths back.
  CHECK(std::sqrt(published_sq / fitted_sq) < 0.7);
}

TEST_CASE("lag smoother: no smoothing next to an invalid, a non-consecutive or a jumped frame") {
  const JointPositions a = body({0, 0}), b = body({0, 0}, 0.6), c = body({0, 0}, 0.9);
  const auto second = [&](bool valid_a, bool valid_c, bool follows_c, const JointPositions& third) {
    LagSmoother lag;
    lag.push(a, valid_a, true);
    lag.push(b, true, true);
    const JointPositions* out = lag.push(third, valid_c, follows_c);
    REQUIRE(out != nullptr);
    return *out;
  };
  // Valid, consecutive, near neighbours: the arm, raised unevenly, is smoothed towards both.
  CHECK(max_distance(second(true, true, true, c), b) > 10);
  CHECK(max_distance(second(false, true, true, c), b) == 0);
  CHECK(max_distance(second(true, false, true, c), b) == 0);
  CHECK(max_distance(second(true, true, false, c), b) == 0);
  // A re-acquisition 200 mm away (beyond paper 6's 150 mm jump) is no neighbour.
  CHECK(max_distance(second(true, true, true, body({200, 0}, 0.9)), b) == 0);
}

TEST_CASE("lag smoother: a released frame is the previous frame of the next hold") {
  LagSmoother lag;
  lag.push(body({0, 0}), true, true);
  REQUIRE(lag.release() != nullptr);  // no next frame came in time
  CHECK(lag.push(body({0, 0}, 0.6), true, true) == nullptr);
  const JointPositions* out = lag.push(body({0, 0}, 0.9), true, true);
  REQUIRE(out != nullptr);
  CHECK(max_distance(*out, body({0, 0}, 0.6)) > 10);  // smoothed with the released frame
}

TEST_CASE("--lag-frames takes 0 or 1") {
  CHECK(parse_lag_frames("0") == 0);
  CHECK(parse_lag_frames("1") == 1);
  CHECK_THROWS_AS(parse_lag_frames("2"), Error);
  CHECK_THROWS_AS(parse_lag_frames("-1"), Error);
  CHECK_THROWS_AS(parse_lag_frames("one"), Error);
}
