// The real CMU clips of ../shared/data/mocap (label "integration": forward kinematics of every
// frame of ten clips is slow under the sanitizers; the parser's own cases are in test_bvh.cpp).
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <filesystem>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/bvh.hpp"
#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/rig_gen.hpp"

using namespace hullpose;
using namespace hullpose::synth;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {
const fs::path kMocap = fs::path(HULLPOSE_SHARED_DIR) / "data" / "mocap";
}  // namespace

TEST_CASE("a clip missing a mapped joint names the joint") {
  BvhClip clip = load_bvh(kMocap / "07_01.bvh");
  const int i = clip.find("LeftForeArm");
  REQUIRE(i >= 0);
  clip.joints[static_cast<size_t>(i)].name = "LeftLowerArm";
  CHECK_THROWS_WITH(make_bvh_motion(clip, {}),
                    Contains("missing joint 'LeftForeArm'") && Contains("LElb"));
}

// An independent FK: homogeneous 4x4 transforms built channel by channel.
Eigen::Vector3d fk_homogeneous(const BvhClip& clip, int frame, int joint) {
  std::vector<Eigen::Matrix4d> world(clip.joints.size());
  for (size_t i = 0; i < clip.joints.size(); ++i) {
    const BvhJoint& j = clip.joints[i];
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<3, 1>(0, 3) = j.offset;
    for (size_t c = 0; c < j.channels.size(); ++c) {
      const double v =
          clip.motion[static_cast<size_t>(frame * clip.channel_count + j.first_channel) + c];
      Eigen::Matrix4d step = Eigen::Matrix4d::Identity();
      const double a = v * M_PI / 180;
      switch (j.channels[c]) {
        case BvhChannel::Xposition:
          step(0, 3) = v;
          break;
        case BvhChannel::Yposition:
          step(1, 3) = v;
          break;
        case BvhChannel::Zposition:
          step(2, 3) = v;
          break;
        case BvhChannel::Xrotation:
          step.block<3, 3>(0, 0) << 1, 0, 0, 0, cos(a), -sin(a), 0, sin(a), cos(a);
          break;
        case BvhChannel::Yrotation:
          step.block<3, 3>(0, 0) << cos(a), 0, sin(a), 0, 1, 0, -sin(a), 0, cos(a);
          break;
        case BvhChannel::Zrotation:
          step.block<3, 3>(0, 0) << cos(a), -sin(a), 0, sin(a), cos(a), 0, 0, 0, 1;
          break;
      }
      m = m * step;
    }
    world[i] = j.parent < 0 ? m : Eigen::Matrix4d(world[static_cast<size_t>(j.parent)] * m);
  }
  return world[static_cast<size_t>(joint)].block<3, 1>(0, 3);
}

TEST_CASE("every clip in the shared mocap folder parses and maps to the 25 joints") {
  int clips = 0;
  for (const auto& entry : fs::directory_iterator(kMocap)) {
    if (entry.path().extension() != ".bvh") continue;
    ++clips;
    INFO(entry.path().filename().string());
    const BvhClip clip = load_bvh(entry.path());
    CHECK(clip.frames > 300);
    CHECK(clip.frame_time_s == Approx(1.0 / 120).epsilon(1e-3));

    // FK against the independent homogeneous computation on a few frames, every joint.
    std::vector<Eigen::Matrix3d> r;
    std::vector<Eigen::Vector3d> p;
    for (int f : {0, clip.frames / 3, clip.frames - 1}) {
      clip.forward_kinematics(f, r, p);
      double worst = 0;
      for (size_t j = 0; j < clip.joints.size(); ++j)
        worst = std::max(worst, (p[j] - fk_homogeneous(clip, f, static_cast<int>(j))).norm());
      CHECK(worst < 1e-9);
    }

    const auto motion = make_bvh_motion(clip, {});
    CHECK(motion->stature_mm() > 1000);
    CHECK(motion->stature_mm() < 2100);
    JointPositions q;
    motion->sample(motion->duration_s() / 2, q);
    for (const auto& v : q) CHECK(v.allFinite());
    // Every bone has a length (zero-length End Sites are continued, see motion.cpp).
    for (const auto& b : kBones) CHECK((q[index(b.parent)] - q[index(b.child)]).norm() > 10);
  }
  CHECK(clips == 10);
}

TEST_CASE("55_01 gives the thesis' 451 frames at 30 fps, upright, on the floor, centred") {
  MotionOptions o;
  o.centre_mm = Eigen::Vector3d(100, -50, 0);
  const auto m = load_bvh_motion(kMocap / "55_01.bvh", o);
  CHECK(m->frame_count(30) == 451);
  CHECK(m->frame_count(120) == 1807);
  JointPositions q;
  m->sample(0, q);
  // Z is up: the head is above the pelvis, the pelvis above the ankles.
  CHECK(q[index(Joint::HeadTop)].z() > q[index(Joint::LBack)].z() + 400);
  CHECK(q[index(Joint::LBack)].z() > q[index(Joint::LAnk)].z() + 600);
  // Left is left: facing direction x lateral x up is consistent (LHip on the subject's left).
  const Eigen::Vector3d lat = q[index(Joint::LHip)] - q[index(Joint::RHip)];
  CHECK(lat.norm() > 100);
  CHECK(q[index(Joint::HeadTop)].z() < m->stature_mm() + 50);
  // Bone lengths are rigid over the clip (FK, units and axis change are all rigid).
  JointPositions q2;
  m->sample(876 * m->duration_s() / 1807, q2);  // a frame time: no blending
  for (const auto& b : kBones) {
    // Finger joints bend the hand and the spine bends between Back and UBack: not rigid.
    if (b.name == "Hand" || b.name == "Upper spine") continue;
    const double l1 = (q[index(b.parent)] - q[index(b.child)]).norm();
    const double l2 = (q2[index(b.parent)] - q2[index(b.child)]).norm();
    INFO(b.name);
    CHECK(std::abs(l1 - l2) < 1e-3);  // the files carry 2e-6-unit offsets at coinciding joints
  }
}

TEST_CASE("the three naming schemes map to skeletons of human proportions") {
  for (const char* file : {"07_01.bvh", "131_01.bvh", "60_01.bvh"}) {
    INFO(file);
    const auto m = load_bvh_motion(kMocap / file, {});
    JointPositions q;
    m->sample(0, q);
    const double thigh = (q[index(Joint::LHip)] - q[index(Joint::LKne)]).norm();
    const double shin = (q[index(Joint::LKne)] - q[index(Joint::LAnk)]).norm();
    CHECK(thigh / m->stature_mm() == Approx(0.24).margin(0.05));
    CHECK(shin / m->stature_mm() == Approx(0.24).margin(0.05));
  }
}

TEST_CASE("the thesis subject stays inside the default capture volume") {
  const Rig rig = make_ring_rig({});
  const auto m = load_bvh_motion(fs::path(HULLPOSE_SHARED_DIR) / "data/mocap/55_01.bvh", {});
  JointPositions q;
  for (int f = 0; f < m->frame_count(30); f += 5) {
    m->sample(f / 30.0, q);
    for (const auto& p : q) {
      CHECK((p.head<2>().array() > rig.volume.min_mm.head<2>().array() + 100).all());
      CHECK((p.head<2>().array() < rig.volume.max_mm.head<2>().array() - 100).all());
      CHECK(p.z() > 0);
      CHECK(p.z() < rig.volume.max_mm.z() - 100);
    }
  }
}
