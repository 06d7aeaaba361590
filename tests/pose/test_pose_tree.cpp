// Pose tree and labels on hand-built skeletons (paper 5).
#include <catch2/catch.hpp>

#include "hullpose/pose/pose_tree.hpp"
#include "stick_figure.hpp"

using namespace hullpose;
using namespace hullpose::pose;
using namespace hullpose::pose::test;

namespace {

constexpr double kStature = 1750;
// The model joint each labelled extremity of a stick figure ends on.
constexpr std::array<Joint, kNumExtremities> kTip = {Joint::HeadTop, Joint::LFTip, Joint::RFTip,
                                                     Joint::LToe, Joint::RToe};
constexpr std::array<const char*, kNumExtremities> kExtremityName = {
    "head", "left hand", "right hand", "left foot", "right foot"};

int nearest_node(const LabelledTree& t, const Eigen::Vector3d& p) {
  int best = 0;
  for (size_t i = 0; i < t.position.size(); ++i)
    if ((t.position[i] - p).norm() < (t.position[best] - p).norm()) best = static_cast<int>(i);
  return best;
}

// tip_voxels: how far a labelled extremity may lie from the true tip. A spur near a tip that is
// longer than the tip beyond it replaces the tip, so noisy skeletons get the spur length.
void check_labels(const LabelledTree& t, const JointPositions& truth, double tip_voxels = 2.5) {
  INFO("why: " << t.why);
  REQUIRE(t.valid);
  const double tol = tip_voxels * t.voxel_mm;
  for (int s = 0; s < kNumExtremities; ++s) {
    INFO(kExtremityName[s]);
    CHECK((t.position[t.extremity[s]] - truth[index(kTip[s])]).norm() < tol);
  }
  CHECK((t.position[t.origin] - truth[index(Joint::Chest)]).norm() < 4 * t.voxel_mm);
  CHECK((t.position[t.pelvis] - truth[index(Joint::LBack)]).norm() < 4 * t.voxel_mm);
  CHECK(t.part[nearest_node(t, truth[index(Joint::LElb)])] == Part::LArm);
  CHECK(t.part[nearest_node(t, truth[index(Joint::RElb)])] == Part::RArm);
  CHECK(t.part[nearest_node(t, truth[index(Joint::LKne)])] == Part::LLeg);
  CHECK(t.part[nearest_node(t, truth[index(Joint::RKne)])] == Part::RLeg);
  CHECK(t.part[nearest_node(t, truth[index(Joint::Back)])] == Part::Torso);
  CHECK(t.part[nearest_node(t, truth[index(Joint::Head)])] == Part::Neck);
}

const LabelledTree& build(PoseTreeBuilder& b, const std::vector<Eigen::Vector3i>& voxels,
                          const VoxelGridSpec& g) {
  return b.build(voxels, g, TemporalHint{});
}

}  // namespace

TEST_CASE("an ideal T-pose tree is labelled, facing any direction") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  for (double yaw : {0.0, 37.0, 90.0, 180.0, 271.0}) {
    INFO("yaw " << yaw);
    const JointPositions truth = stick_figure(kStature, t_pose(), {yaw, 0, 0, 0});
    const LabelledTree& t = build(builder, rasterise(g, truth), g);
    check_labels(t, truth);
    CHECK(t.quality > 0.9);
    // Facing +y at yaw 0.
    const Eigen::Vector3d facing(-std::sin(yaw * M_PI / 180), std::cos(yaw * M_PI / 180), 0);
    CHECK(t.forward.dot(facing) > 0.95);
    CHECK(t.up.z() > 0.95);
  }
}

TEST_CASE("the tree is labelled at 64^3 too") {
  const VoxelGridSpec g = grid_2m(64);
  PoseTreeBuilder builder;
  const JointPositions truth = stick_figure(kStature, t_pose(), {20, 0, 0, 0});
  check_labels(build(builder, rasterise(g, truth), g), truth);
}

TEST_CASE("spurious branches are pruned") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    INFO("seed " << seed);
    const JointPositions truth = stick_figure(kStature, t_pose(), {15.0 * seed, 0, 0, 0});
    auto voxels = rasterise(g, truth);
    add_spurs(g, voxels, 25, 6, seed);
    check_labels(build(builder, voxels, g), truth, 8);
  }
}

TEST_CASE("head not the highest point: hands above the head, and upside down") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  Limbs up = t_pose();
  up.l_upper_arm = {0.35, 0, 1};
  up.l_forearm = {0.1, 0.05, 1};
  up.r_upper_arm = {-0.35, 0, 1};
  up.r_forearm = {-0.1, 0.05, 1};
  const JointPositions hands_up = stick_figure(kStature, up, {60, 0, 0, 0});
  REQUIRE(hands_up[index(Joint::LFTip)].z() > hands_up[index(Joint::HeadTop)].z() + 200);
  check_labels(build(builder, rasterise(g, hands_up), g), hands_up);

  Limbs bent = t_pose();  // bent knees so a handstand still has a forward direction from legs
  bent.l_shin = bent.r_shin = {0, -0.5, -1};
  const JointPositions handstand = stick_figure(kStature, bent, {0, 180, 0, 0});
  REQUIRE(handstand[index(Joint::LToe)].z() > handstand[index(Joint::HeadTop)].z());
  check_labels(build(builder, rasterise(g, handstand), g), handstand);
}

TEST_CASE("an arm above the head") {
  const VoxelGridSpec g = grid_tall(128);
  PoseTreeBuilder builder;
  Limbs p = t_pose();
  p.l_upper_arm = {0.1, 0, 1};
  p.l_forearm = {0, 0, 1};
  p.r_upper_arm = {-0.4, 0.1, -1};
  p.r_forearm = {-0.2, 0.4, -1};
  const JointPositions truth = stick_figure(kStature, p, {-30, 0, 0, 0});
  check_labels(build(builder, rasterise(g, truth), g), truth);
}

TEST_CASE("crossed legs keep their sides") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  Limbs p = t_pose();
  p.l_thigh = {-0.15, 0.15, -1};
  p.l_shin = {-0.2, 0, -1};
  p.r_thigh = {0.15, -0.15, -1};
  p.r_shin = {0.2, 0, -1};
  const JointPositions truth = stick_figure(kStature, p, {120, 0, 0, 0});
  // Crossed: the left foot is right of the right foot (x grows to the subject's right at yaw 0).
  const LabelledTree& t = build(builder, rasterise(g, truth), g);
  check_labels(t, truth);
  CHECK((truth[index(Joint::LToe)] - truth[index(Joint::RToe)]).dot(t.left) < 0);
}

TEST_CASE("feet together") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  Limbs p = t_pose();
  p.l_thigh = {-0.1, 0, -1};
  p.r_thigh = {0.1, 0, -1};
  p.l_shin = {-0.05, 0, -1};
  p.r_shin = {0.05, 0, -1};
  const JointPositions truth = stick_figure(kStature, p, {200, 0, 0, 0});
  const double apart = (truth[index(Joint::LAnk)] - truth[index(Joint::RAnk)]).norm();
  REQUIRE(apart < 4 * g.voxel_mm);
  check_labels(build(builder, rasterise(g, truth), g), truth);
}

TEST_CASE("a skeleton without arms is invalid, never mislabelled") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  const JointPositions truth = stick_figure(kStature, t_pose());
  std::vector<Eigen::Vector3i> voxels;
  for (const Bone& b : kBones) {
    const std::string_view n = name(b.child);
    if (n == "LSho" || n == "RSho" || n == "LElb" || n == "RElb" || n == "LHand" || n == "RHand" ||
        n == "LFTip" || n == "RFTip")
      continue;
    rasterise_segment(g, truth[index(b.parent)], truth[index(b.child)], voxels);
  }
  dedupe(voxels);
  const LabelledTree& t = build(builder, voxels, g);
  CHECK_FALSE(t.valid);
  CHECK(std::string(t.why) == "fewer than five extremities");

  CHECK_FALSE(build(builder, {}, g).valid);
  CHECK(std::string(builder.tree().why) == "no skeleton voxels");
}

TEST_CASE("voxels outside the grid, repeats and a stray blob above the head are ignored") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  const JointPositions truth = stick_figure(kStature, t_pose(), {45, 0, 0, 0});
  auto voxels = rasterise(g, truth);
  const auto copy = voxels;
  voxels.insert(voxels.end(), copy.begin(), copy.begin() + 40);  // repeats
  voxels.push_back({-5, 3, 7});
  voxels.push_back({1000, 3, 7});
  for (int k = 0; k < 6; ++k) voxels.push_back({60 + k, 64, 125});  // a stray line near the ceiling
  check_labels(build(builder, voxels, g), truth);
}

TEST_CASE("temporal correspondence keeps left and right when the geometry cannot tell") {
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  const JointPositions truth = stick_figure(kStature, t_pose(), {10, 0, 0, 0});
  const auto voxels = rasterise(g, truth);
  const LabelledTree& first = build(builder, voxels, g);
  REQUIRE(first.valid);
  TemporalHint hint;
  hint.valid = true;
  for (int s = 0; s < kNumExtremities; ++s)
    hint.extremity_mm[s] = first.position[first.extremity[s]];
  hint.forward = first.forward;
  const LabelledTree& second = builder.build(voxels, g, hint);
  check_labels(second, truth);
}

TEST_CASE("a long spur between the legs does not push out the head") {
  // The visual hull's ghost volume between the legs thins to a branch longer than the head's.
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  const JointPositions truth = stick_figure(kStature, t_pose(), {75, 0, 0, 0});
  auto voxels = rasterise(g, truth);
  const Eigen::Vector3d pelvis = truth[index(Joint::LBack)];
  rasterise_segment(g, pelvis, pelvis - Eigen::Vector3d(0, 0, 350), voxels);
  dedupe(voxels);
  REQUIRE(350 > (truth[index(Joint::HeadTop)] - truth[index(Joint::Chest)]).norm());
  check_labels(build(builder, voxels, g), truth);
}

TEST_CASE("a spur off the chest as long as the neck is not taken for the head") {
  // CK3 grows spurs off a thick chest or back about as long as the chest is deep, which is the
  // neck's length; a head often thins short of its crown. Only direction tells them apart: the
  // neck continues the torso, the spur leaves it sideways or downwards.
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  for (double yaw : {0.0, 130.0}) {
    INFO("yaw " << yaw);
    const JointPositions truth = stick_figure(kStature, t_pose(), {yaw, 0, 0, 0});
    std::vector<Eigen::Vector3i> voxels;
    for (const Bone& b : kBones)
      if (b.child != Joint::HeadTop)
        rasterise_segment(g, truth[index(b.parent)], truth[index(b.child)], voxels);
    const Eigen::Vector3d from = truth[index(Joint::Chest)];
    const Eigen::Vector3d forward_down =
        Eigen::AngleAxisd(yaw * M_PI / 180, Eigen::Vector3d::UnitZ()) *
        Eigen::Vector3d(0, 1, -0.3).normalized();
    const double neck = (truth[index(Joint::HeadTop)] - truth[index(Joint::Chest)]).norm();
    rasterise_segment(g, from, from + neck * forward_down, voxels);
    dedupe(voxels);
    const LabelledTree& t = build(builder, voxels, g);
    INFO("why: " << t.why);
    REQUIRE(t.valid);
    CHECK((t.position[t.extremity[static_cast<int>(Extremity::Head)]] - truth[index(Joint::Head)])
              .norm() < 2.5 * g.voxel_mm);
    CHECK((t.position[t.extremity[static_cast<int>(Extremity::LHand)]] - truth[index(Joint::LFTip)])
              .norm() < 2.5 * g.voxel_mm);
  }
}

TEST_CASE("pruning never removes one of the last five branches") {
  // A head that thins to a stub (or whose branch point moves up the neck under raised arms)
  // is shorter than the spur threshold; whether it is a limb is the ranking's decision.
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  const JointPositions truth = stick_figure(kStature, t_pose(), {20, 0, 0, 0});
  std::vector<Eigen::Vector3i> voxels;
  for (const Bone& b : kBones)
    if (b.child != Joint::Head && b.child != Joint::HeadTop)
      rasterise_segment(g, truth[index(b.parent)], truth[index(b.child)], voxels);
  dedupe(voxels);
  const LabelledTree& t = build(builder, voxels, g);
  REQUIRE(std::string_view(t.why) != "fewer than five extremities");
  REQUIRE(t.extremity[static_cast<int>(Extremity::Head)] >= 0);
  CHECK((t.position[t.extremity[static_cast<int>(Extremity::Head)]] - truth[index(Joint::Neck)])
            .norm() < 2.5 * g.voxel_mm);
}

TEST_CASE("a skeleton cut off by the side of the capture volume is invalid") {
  // Walking out of the volume: the hull, and with it a foot or a hand, is cut at the side.
  const VoxelGridSpec g = grid_2m(128);
  PoseTreeBuilder builder;
  const JointPositions inside = stick_figure(kStature, t_pose(), {0, 0, 0, 0});
  REQUIRE(build(builder, rasterise(g, inside), g).valid);
  for (const Eigen::Vector3d& shift : {Eigen::Vector3d(0, 950, 0), Eigen::Vector3d(-300, 0, 0)}) {
    JointPositions moved = inside;
    for (auto& p : moved) p += shift;
    std::vector<Eigen::Vector3i> voxels;
    for (const Eigen::Vector3i& v : rasterise(g, moved))
      if (g.contains(v)) voxels.push_back(v);
    const LabelledTree& t = build(builder, voxels, g);
    CHECK_FALSE(t.valid);
    CHECK_THAT(t.why, Catch::Contains("partly outside"));
  }
}

TEST_CASE("a skeleton that reads the same upside down is labelled upright") {
  // Arms hanging beside the legs make the upright and the upside-down readings rank alike (on
  // CMU 131_02 the feet became hands and a knee spur the head). A mirror-symmetric tree ranks
  // exactly alike both ways: the upright reading must win.
  const VoxelGridSpec g = grid_tall(128);
  PoseTreeBuilder builder;
  for (double yaw : {0.0, 40.0, 90.0, 200.0}) {
    INFO("yaw " << yaw);
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(yaw * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d chest(0, 0, 1400), pelvis(0, 0, 900), up(0, 0, 1);
    std::vector<Eigen::Vector3i> voxels;
    auto segment = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      rasterise_segment(g, turn * a, turn * b, voxels);
    };
    segment(pelvis, chest);
    segment(chest, chest + 280 * up);
    segment(pelvis, pelvis - 280 * up);
    for (double side : {-1.0, 1.0}) {
      segment(chest, chest + Eigen::Vector3d(side * 350, 60, 720));
      segment(pelvis, pelvis + Eigen::Vector3d(side * 350, 60, -720));
    }
    dedupe(voxels);
    const LabelledTree& t = build(builder, voxels, g);
    REQUIRE(t.origin >= 0);
    CHECK(t.position[t.origin].z() > 1300);
    CHECK(t.position[t.extremity[static_cast<int>(Extremity::Head)]].z() > 1600);
  }
}
