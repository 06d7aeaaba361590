#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/bvh.hpp"
#include "hullpose/synth/motion.hpp"

using namespace hullpose;
using namespace hullpose::synth;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

// Root at (1, 2, 3) with ZYX channels, one child joint with ZXY channels, one End Site.
std::string two_joint_bvh(const std::string& frames, const std::string& nl = "\n",
                          const std::string& child_channels = "Zrotation Xrotation Yrotation") {
  std::string s =
      "HIERARCHY\nROOT Root\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition "
      "Zrotation Yrotation Xrotation\n  JOINT Arm\n  {\n    OFFSET 10 0 0\n    CHANNELS 3 " +
      child_channels +
      "\n    End Site\n    {\n      OFFSET 0 5 0\n    }\n  }\n}\nMOTION\nFrames: 2\n"
      "Frame Time: 0.0083333\n" +
      frames;
  std::string out;
  for (char c : s) out += c == '\n' ? nl : std::string(1, c);
  return out;
}
const std::string kFrames = "1 2 3 0 0 0 0 0 0\n1 2 3 90 0 0 0 90 0\n";

std::string error_of(const std::string& text) {
  try {
    parse_bvh(text, "bad.bvh");
  } catch (const hullpose::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("forward kinematics of a hand-made clip gives the hand-computed positions") {
  const BvhClip clip = parse_bvh(two_joint_bvh(kFrames), "two.bvh");
  REQUIRE(clip.joints.size() == 3);
  CHECK(clip.joints[2].name == "Arm_End");
  std::vector<Eigen::Matrix3d> r;
  std::vector<Eigen::Vector3d> p;
  clip.forward_kinematics(0, r, p);
  CHECK((p[1] - Eigen::Vector3d(11, 2, 3)).norm() < 1e-12);
  CHECK((p[2] - Eigen::Vector3d(11, 7, 3)).norm() < 1e-12);
  // Frame 2: root turned 90 deg about Z: the arm offset (10,0,0) becomes (0,10,0). The arm's
  // own 90 deg about X (ZXY order) turns its end site (0,5,0) into (0,0,5), then the root's Z
  // rotation leaves z alone.
  clip.forward_kinematics(1, r, p);
  CHECK((p[1] - Eigen::Vector3d(1, 12, 3)).norm() < 1e-9);
  CHECK((p[2] - Eigen::Vector3d(1, 12, 8)).norm() < 1e-9);
}

TEST_CASE("channel order matters: ZYX and ZXY compose differently") {
  const std::string frames = "0 0 0 0 0 0 90 90 0\n0 0 0 0 0 0 90 90 0\n";
  const BvhClip zxy = parse_bvh(two_joint_bvh(frames), "zxy.bvh");
  const BvhClip zyx =
      parse_bvh(two_joint_bvh(frames, "\n", "Zrotation Yrotation Xrotation"), "zyx.bvh");
  std::vector<Eigen::Matrix3d> r;
  std::vector<Eigen::Vector3d> a, b;
  zxy.forward_kinematics(0, r, a);
  zyx.forward_kinematics(0, r, b);
  // ZXY with Z=90, X=90: Rz * Rx * (0,5,0) = Rz * (0,0,5) = (0,0,5).
  CHECK((a[2] - Eigen::Vector3d(10, 0, 5)).norm() < 1e-9);
  // ZYX with Z=90, Y=90: Rz * Ry * (0,5,0) = Rz * (0,5,0) = (-5,0,0).
  CHECK((b[2] - Eigen::Vector3d(5, 0, 0)).norm() < 1e-9);
}

TEST_CASE("CRLF and mixed line endings parse like LF") {
  const BvhClip lf = parse_bvh(two_joint_bvh(kFrames), "lf.bvh");
  const BvhClip crlf = parse_bvh(two_joint_bvh(kFrames, "\r\n"), "crlf.bvh");
  CHECK(lf.motion == crlf.motion);
  CHECK(crlf.frames == 2);
}

TEST_CASE("bad BVH files give errors naming the line or joint") {
  SECTION("unknown channel") {
    const std::string e = error_of(two_joint_bvh(kFrames, "\n", "Zrotation Wrotation Yrotation"));
    CHECK_THAT(e,
               Contains("bad.bvh:9") && Contains("unknown channel 'Wrotation'") && Contains("Arm"));
  }
  SECTION("NaN in the motion") {
    const std::string e = error_of(two_joint_bvh("1 2 3 0 0 0 0 0 0\n1 2 3 0 nan 0 0 0 0\n"));
    CHECK_THAT(
        e, Contains("bad.bvh:20") && Contains("joint Root Yrotation") && Contains("not finite"));
  }
  SECTION("a short motion line") {
    const std::string e = error_of(two_joint_bvh("1 2 3 0 0 0 0 0 0\n1 2 3 0 0 0 0\n"));
    CHECK_THAT(e, Contains("bad.bvh:20") && Contains("joint Arm") && Contains("value missing"));
  }
  SECTION("truncated motion") {
    const std::string e = error_of(two_joint_bvh("1 2 3 0 0 0 0 0 0\n"));
    CHECK_THAT(e, Contains("truncated motion") && Contains("2 frames") && Contains("holds 1"));
  }
  SECTION("a lying frame count") {
    std::string text = two_joint_bvh(kFrames);
    text.replace(text.find("Frames: 2"), 9, "Frames: 9999999");
    CHECK_THAT(error_of(text), Contains("truncated motion") && Contains("9999999 frames"));
  }
  SECTION("garbage in the hierarchy") {
    std::string text = two_joint_bvh(kFrames);
    text.replace(text.find("OFFSET 10"), 9, "OFFSET xx");
    CHECK_THAT(error_of(text), Contains("bad.bvh:8") && Contains("OFFSET of joint Arm"));
  }
  SECTION("cut off inside the hierarchy") {
    std::string text = two_joint_bvh(kFrames);
    CHECK_THAT(error_of(text.substr(0, text.find("End Site"))), Contains("unexpected end of file"));
  }
  SECTION("no known naming scheme") {
    const BvhClip clip = parse_bvh(two_joint_bvh(kFrames), "two.bvh");
    CHECK_THROWS_WITH(make_bvh_motion(clip, {}),
                      Contains("two.bvh") && Contains("unknown joint naming scheme"));
  }
}
