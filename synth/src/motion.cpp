#include "hullpose/synth/motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/avatar.hpp"

namespace hullpose::synth {
namespace {

// Where one of the 25 joints sits on a BVH skeleton: in the frame of BVH joint `joint`, at
// `fraction` of the offset of its child `toward` plus `local` (file units). Virtual points
// (fraction or local set) fill joints the BVH skeleton lacks; synth/README.md explains.
// Some releases (02_01) write zero-length End Sites: then an End Site stands at `if_zero` times
// its parent's bone, continued.
struct JointSource {
  const char* joint;
  const char* toward = nullptr;
  double fraction = 0;
  Eigen::Vector3d local = Eigen::Vector3d::Zero();
  double if_zero = 0;
};
using JointMap = std::array<JointSource, kNumJoints>;

// Order: HeadTop Head Neck Chest LSho RSho LElb RElb LHand RHand LFTip RFTip UBack Back LBack
//        LHip RHip LKne RKne LAnk RAnk LFoot RFoot LToe RToe.
const JointMap& scheme_map(BvhScheme s) {
  static const JointMap a = {{{"Head_End", nullptr, 0, {0, 0, 0}, 1.0},
                              {"Head"},
                              {"Neck1"},
                              {"Spine1"},
                              {"LeftArm"},
                              {"RightArm"},
                              {"LeftForeArm"},
                              {"RightForeArm"},
                              {"LeftHand"},
                              {"RightHand"},
                              {"LeftHandIndex1_End", nullptr, 0, {0, 0, 0}, 0.8},
                              {"RightHandIndex1_End", nullptr, 0, {0, 0, 0}, 0.8},
                              {"Spine", "Spine1", 1.0 / 3},
                              {"LowerBack", "Spine", 2.0 / 3},
                              {"Hips"},
                              {"LeftUpLeg"},
                              {"RightUpLeg"},
                              {"LeftLeg"},
                              {"RightLeg"},
                              {"LeftFoot"},
                              {"RightFoot"},
                              {"LeftToeBase"},
                              {"RightToeBase"},
                              {"LeftToeBase_End", nullptr, 0, {0, 0, 0}, 0.5},
                              {"RightToeBase_End", nullptr, 0, {0, 0, 0}, 0.5}}};
  static const JointMap b = {{{"Head_End", nullptr, 0, {0, 0, 0}, 1.0},
                              {"Head"},
                              {"Neck"},
                              {"Chest2"},
                              {"LeftShoulder"},
                              {"RightShoulder"},
                              {"LeftElbow"},
                              {"RightElbow"},
                              {"LeftWrist"},
                              {"RightWrist"},
                              {"LFingers_End", nullptr, 0, {0, 0, 0}, 0.8},
                              {"RFingers_End", nullptr, 0, {0, 0, 0}, 0.8},
                              {"Chest", "Chest2", 1.0 / 3},
                              {"lowerback", "Chest", 2.0 / 3},
                              {"Hips"},
                              {"LeftHip"},
                              {"RightHip"},
                              {"LeftKnee"},
                              {"RightKnee"},
                              {"LeftAnkle"},
                              {"RightAnkle"},
                              {"LeftToe"},
                              {"RightToe"},
                              {"LeftToe_End", nullptr, 0, {0, 0, 0}, 0.5},
                              {"RightToe_End", nullptr, 0, {0, 0, 0}, 0.5}}};
  // Scheme C has no head end site and no toe joint: Head and HeadTop are points on the head's
  // axis (65 and 135 mm-equivalents above the head joint, i.e. eye level and crown), LFoot is
  // two thirds of the way from the ankle to the toe tip.
  static const JointMap c = {{{"head", nullptr, 0, Eigen::Vector3d(0, 0.135, 0)},
                              {"head", nullptr, 0, Eigen::Vector3d(0, 0.065, 0)},
                              {"head"},
                              {"neck"},
                              {"lShldr"},
                              {"rShldr"},
                              {"lForeArm"},
                              {"rForeArm"},
                              {"lHand"},
                              {"rHand"},
                              {"lMid2_End"},
                              {"rMid2_End"},
                              {"chest"},
                              {"abdomen"},
                              {"hip"},
                              {"lThigh"},
                              {"rThigh"},
                              {"lShin"},
                              {"rShin"},
                              {"lFoot"},
                              {"rFoot"},
                              {"lFoot", "lFoot_End", 2.0 / 3},
                              {"rFoot", "rFoot_End", 2.0 / 3},
                              {"lFoot_End"},
                              {"rFoot_End"}}};
  switch (s) {
    case BvhScheme::A:
      return a;
    case BvhScheme::B:
      return b;
    case BvhScheme::C:
      return c;
  }
  return a;
}

struct ResolvedSource {
  int joint;
  Eigen::Vector3d local;  // file units, in the joint's frame
};

// BVH is y up; the rig is z up: (x, y, z)_bvh -> (x, -z, y)_rig, a proper rotation.
Eigen::Vector3d to_rig(const Eigen::Vector3d& v) {
  return {v.x(), -v.z(), v.y()};
}

class BvhMotion final : public Motion {
 public:
  BvhMotion(std::string name, double stature, double frame_time, std::vector<JointPositions> frames)
      : Motion(std::move(name), stature), frame_time_(frame_time), frames_(std::move(frames)) {}

  double duration_s() const override { return static_cast<double>(frames_.size()) * frame_time_; }

  void sample(double t_s, JointPositions& out) const override {
    const double s = std::clamp(t_s / frame_time_, 0.0, static_cast<double>(frames_.size() - 1));
    const auto i0 = static_cast<size_t>(std::floor(s));
    const size_t i1 = std::min(i0 + 1, frames_.size() - 1);
    const double w = s - static_cast<double>(i0);
    for (size_t j = 0; j < out.size(); ++j) out[j] = (1 - w) * frames_[i0][j] + w * frames_[i1][j];
  }

 private:
  double frame_time_;
  std::vector<JointPositions> frames_;
};

double lowest_sole(const BodyShape& body, const JointPositions& p) {
  double z = std::numeric_limits<double>::infinity();
  for (Joint j : {Joint::LAnk, Joint::RAnk, Joint::LFoot, Joint::RFoot, Joint::LToe, Joint::RToe})
    z = std::min(z, p[static_cast<size_t>(index(j))].z() - body.sole_radius_mm(j));
  return z;
}

}  // namespace

const char* scheme_name(BvhScheme s) {
  switch (s) {
    case BvhScheme::A:
      return "A (CMU/MotionBuilder)";
    case BvhScheme::B:
      return "B (CMU/3dsMax)";
    case BvhScheme::C:
      return "C (DAZ/Poser)";
  }
  return "?";
}

BvhScheme detect_scheme(const BvhClip& clip) {
  if (clip.find("LeftUpLeg") >= 0) return BvhScheme::A;
  if (clip.find("LeftKnee") >= 0) return BvhScheme::B;
  if (clip.find("lThigh") >= 0) return BvhScheme::C;
  HULLPOSE_THROW(
      clip.source << ": unknown joint naming scheme (none of LeftUpLeg (A), LeftKnee (B), "
                     "lThigh (C) is in the hierarchy)");
}

int Motion::frame_count(double fps) const {
  HULLPOSE_THROW_UNLESS(std::isfinite(duration_s()),
                        "motion '" << name() << "' has no end: give the number of frames");
  HULLPOSE_THROW_UNLESS(fps > 0, "frame rate must be positive, got " << fps);
  // The small slack absorbs headers that round the frame time (0.00833333 s).
  return static_cast<int>(std::floor(duration_s() * fps + 1e-3));
}

std::unique_ptr<Motion> make_bvh_motion(const BvhClip& clip, const MotionOptions& options) {
  const BvhScheme scheme = detect_scheme(clip);
  const JointMap& map = scheme_map(scheme);
  std::array<ResolvedSource, kNumJoints> src;
  for (size_t k = 0; k < src.size(); ++k) {
    const JointSource& s = map[k];
    int j = clip.find(s.joint);
    HULLPOSE_THROW_UNLESS(j >= 0, clip.source << ": missing joint '" << s.joint << "' (needed for "
                                              << kJointNames[k] << ", naming scheme "
                                              << scheme_name(scheme) << ")");
    Eigen::Vector3d local = s.local;
    const BvhJoint& named = clip.joints[static_cast<size_t>(j)];
    if (s.if_zero > 0 && named.channels.empty() && named.offset.norm() < 1e-6 &&
        named.parent >= 0) {
      j = named.parent;
      local = s.if_zero * clip.joints[static_cast<size_t>(j)].offset;
    }
    if (s.toward) {
      const int t = clip.find(s.toward);
      HULLPOSE_THROW_UNLESS(t >= 0 && clip.joints[static_cast<size_t>(t)].parent == j,
                            clip.source << ": missing joint '" << s.toward << "' as a child of '"
                                        << s.joint << "' (needed for " << kJointNames[k] << ")");
      local += s.fraction * clip.joints[static_cast<size_t>(t)].offset;
    }
    src[k] = {j, local};
  }
  const double mm = options.bvh_mm_per_unit > 0 ? options.bvh_mm_per_unit
                                                : (scheme == BvhScheme::C ? 1000.0 : kCmuUnitMm);

  std::vector<Eigen::Matrix3d> rot;
  std::vector<Eigen::Vector3d> pos;
  auto joints_at = [&](int frame, JointPositions& out) {
    clip.forward_kinematics(frame, rot, pos);
    for (size_t k = 0; k < src.size(); ++k) {
      const auto j = static_cast<size_t>(src[k].joint);
      out[k] = to_rig(pos[j] + rot[j] * src[k].local) * mm;
    }
  };

  // Stature of the subject standing upright: the rest pose's upper body (pelvis to crown) plus
  // straight vertical legs plus the rest pose's ankle-to-sole height. Legs are measured along
  // their bones because some rest poses (scheme B) splay them. Girths, and so the soles, scale
  // with the joint extent.
  JointPositions rest;
  joints_at(-1, rest);
  auto at = [&](Joint j) -> const Eigen::Vector3d& { return rest[static_cast<size_t>(index(j))]; };
  const double upper = at(Joint::HeadTop).z() - 0.5 * (at(Joint::LHip).z() + at(Joint::RHip).z());
  const double legs =
      0.5 *
      ((at(Joint::LHip) - at(Joint::LKne)).norm() + (at(Joint::LKne) - at(Joint::LAnk)).norm() +
       (at(Joint::RHip) - at(Joint::RKne)).norm() + (at(Joint::RKne) - at(Joint::RAnk)).norm());
  double ankle_to_joint = 0;
  for (Joint j : {Joint::LFoot, Joint::LToe})
    ankle_to_joint = std::max(ankle_to_joint, at(Joint::LAnk).z() - at(j).z());
  BodyShape body;
  body.build = options.build;
  body.stature_mm = upper + legs + ankle_to_joint;
  const double ankle_to_sole =
      std::max({body.sole_radius_mm(Joint::LAnk),
                at(Joint::LAnk).z() - at(Joint::LFoot).z() + body.sole_radius_mm(Joint::LFoot),
                at(Joint::LAnk).z() - at(Joint::LToe).z() + body.sole_radius_mm(Joint::LToe)});
  const double stature = upper + legs + ankle_to_sole;
  HULLPOSE_THROW_UNLESS(stature > 500 && stature < 2600,
                        clip.source << ": rest-pose stature " << stature << " mm at " << mm
                                    << " mm per unit is not human: wrong units?");
  body.stature_mm = stature;

  std::vector<JointPositions> frames(static_cast<size_t>(clip.frames));
  Eigen::Vector2d lo_xy = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi_xy = -lo_xy;
  double floor = std::numeric_limits<double>::infinity();
  for (int f = 0; f < clip.frames; ++f) {
    auto& p = frames[static_cast<size_t>(f)];
    joints_at(f, p);
    for (const auto& joint : p) {
      lo_xy = lo_xy.cwiseMin(joint.head<2>());
      hi_xy = hi_xy.cwiseMax(joint.head<2>());
    }
    floor = std::min(floor, lowest_sole(body, p));
  }
  // The middle of the space the joints sweep goes to the centre; the lowest sole touches the floor.
  const Eigen::Vector2d mid_xy = 0.5 * (lo_xy + hi_xy);
  const Eigen::Vector3d shift(options.centre_mm.x() - mid_xy.x(),
                              options.centre_mm.y() - mid_xy.y(), options.centre_mm.z() - floor);
  for (auto& p : frames)
    for (auto& j : p) j += shift;
  return std::make_unique<BvhMotion>(std::filesystem::path(clip.source).filename().string(),
                                     stature, clip.frame_time_s, std::move(frames));
}

std::unique_ptr<Motion> load_bvh_motion(const std::filesystem::path& path,
                                        const MotionOptions& options) {
  return make_bvh_motion(load_bvh(path), options);
}

std::unique_ptr<Motion> make_motion(const std::string& spec, const MotionOptions& options) {
  std::string ext = std::filesystem::path(spec).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".bvh") return load_bvh_motion(spec, options);
  return make_builtin_motion(spec, options);
}

}  // namespace hullpose::synth
