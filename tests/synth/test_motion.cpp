#include <catch2/catch.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/avatar.hpp"
#include "hullpose/synth/motion.hpp"

using namespace hullpose;
using namespace hullpose::synth;
using Catch::Matchers::Contains;

namespace {
double lowest_sole(const JointPositions& q, const BodyShape& b) {
  double z = 1e9;
  for (Joint j : {Joint::LAnk, Joint::RAnk, Joint::LFoot, Joint::RFoot, Joint::LToe, Joint::RToe})
    z = std::min(z, q[index(j)].z() - b.sole_radius_mm(j));
  return z;
}
}  // namespace

TEST_CASE("the T-pose has the requested stature, feet on the floor") {
  for (double stature : {1200.0, 1750.0, 1950.0}) {
    MotionOptions o;
    o.stature_mm = stature;
    const auto m = make_builtin_motion("tpose", o);
    CHECK(m->stature_mm() == stature);
    JointPositions q;
    m->sample(0, q);
    BodyShape b{stature, 1.0, 0};
    CHECK(lowest_sole(q, b) == Approx(0).margin(1e-6));
    CHECK(q[index(Joint::HeadTop)].z() == Approx(stature).margin(1e-6));
    // Arms horizontal.
    CHECK(q[index(Joint::LHand)].z() == Approx(q[index(Joint::LSho)].z()).margin(1e-6));
    CHECK(q[index(Joint::LHand)].y() > q[index(Joint::RHand)].y() + 0.8 * stature);
  }
}

TEST_CASE("every built-in motion is rigid, grounded or airborne, and stays in the volume") {
  for (const auto& name : builtin_motion_names()) {
    INFO(name);
    const auto m = make_builtin_motion(name, {});
    CHECK_THROWS_WITH(m->frame_count(30), Contains("no end"));
    JointPositions rest, q;
    m->sample(0, rest);
    BodyShape b;
    for (int f = 0; f < 120; ++f) {
      m->sample(f / 30.0, q);
      for (const auto& bone : kBones)
        CHECK((q[index(bone.parent)] - q[index(bone.child)]).norm() ==
              Approx((rest[index(bone.parent)] - rest[index(bone.child)]).norm()).margin(1e-6));
      CHECK(lowest_sole(q, b) >= -1e-6);
      if (name != "run" && name != "jump") CHECK(lowest_sole(q, b) == Approx(0).margin(1e-6));
      for (const auto& v : q) {
        CHECK(std::abs(v.x()) < 1200);
        CHECK(std::abs(v.y()) < 1200);
        CHECK(v.z() < 2200);
      }
    }
  }
}

TEST_CASE("speed and stride parameters change the motion") {
  MotionOptions slow, fast;
  fast.speed = 2;
  const auto a = make_builtin_motion("walk", slow), b = make_builtin_motion("walk", fast);
  JointPositions qa, qb;
  a->sample(2.0, qa);
  b->sample(1.0, qb);
  CHECK((qa[index(Joint::LBack)] - qb[index(Joint::LBack)]).norm() <
        1e-6);  // same path, twice the pace
  CHECK_THROWS_WITH(make_builtin_motion("moonwalk", {}),
                    Contains("unknown motion 'moonwalk'") && Contains("walk"));
  CHECK_THROWS_WITH(make_motion("missing.bvh", {}), Contains("missing.bvh"));
}
