// Built-in motions: a small articulated body driven by closed-form joint angles, so that every
// test and demo can run without motion-capture files. Bone lengths are the thesis' Table 6.7
// ratios, scaled so that the upright rest pose is exactly the requested stature.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/avatar.hpp"
#include "hullpose/synth/motion.hpp"

namespace hullpose::synth {
namespace {

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Vector3d;

// Pose parameters (radians, mm). Hip flexion moves the knee forward, knee flexion bends the
// shank back, ankle flexion lifts the toes; shoulder abduction raises the arm sideways (pi/2 =
// T-pose), shoulder flexion raises it forwards.
enum P : int {
  kX,
  kY,
  kYaw,
  kLift,
  kLean,
  kTwist,
  kNod,
  kLHipFlex,
  kLHipAbd,
  kLKnee,
  kLAnkle,
  kRHipFlex,
  kRHipAbd,
  kRKnee,
  kRAnkle,
  kLShoAbd,
  kLShoFlex,
  kLElbow,
  kRShoAbd,
  kRShoFlex,
  kRElbow,
  kCount
};
using Pose = std::array<double, kCount>;

double bone(double stature, int i) {
  return kBones[static_cast<size_t>(i)].stature_ratio * stature;
}

class Body {
 public:
  Body(double stature, double build) : shape_{stature, build, 0} {
    // Solve for the length scale k: rest HeadTop height = k * joint extent + sole radius.
    scale_ = 1.0;
    JointPositions p;
    Pose rest{};
    pose(rest, p, false);
    double lowest = std::numeric_limits<double>::infinity();
    for (Joint j : {Joint::LAnk, Joint::LFoot, Joint::LToe})
      lowest = std::min(lowest, p[static_cast<size_t>(index(j))].z());
    const double extent = p[static_cast<size_t>(index(Joint::HeadTop))].z() - lowest;
    const double sole = lowest - lowest_sole(p);
    scale_ = (stature - sole) / extent;
  }

  // Joint positions for pose q; grounded: the lowest sole is put at z = q[kLift].
  void pose(const Pose& q, JointPositions& out, bool grounded = true) const {
    const double s = shape_.stature_mm * scale_;
    auto at = [&](Joint j) -> Vector3d& { return out[static_cast<size_t>(index(j))]; };
    const Matrix3d yaw(AngleAxisd(q[kYaw], Vector3d::UnitZ()));
    const Matrix3d torso =
        yaw * AngleAxisd(q[kTwist], Vector3d::UnitZ()) * AngleAxisd(q[kLean], Vector3d::UnitY());
    const Matrix3d head = torso * AngleAxisd(q[kNod], Vector3d::UnitY());
    const Vector3d up = Vector3d::UnitZ();

    at(Joint::LBack) = Vector3d::Zero();
    at(Joint::Back) = at(Joint::LBack) + torso * up * bone(s, 13);
    at(Joint::UBack) = at(Joint::Back) + torso * up * bone(s, 12);
    at(Joint::Chest) = at(Joint::UBack) + torso * up * bone(s, 11);
    at(Joint::Neck) = at(Joint::Chest) + head * up * bone(s, 0);
    at(Joint::Head) = at(Joint::Neck) + head * up * bone(s, 1);
    at(Joint::HeadTop) = at(Joint::Head) + head * up * bone(s, 2);

    for (int side : {+1, -1}) {
      const bool left = side > 0;
      const Vector3d sho_dir = Vector3d(0, side * 0.97, -0.24).normalized();
      const Vector3d sho = at(Joint::Chest) + torso * sho_dir * bone(s, 3);
      const double abd = q[left ? kLShoAbd : kRShoAbd], flex = q[left ? kLShoFlex : kRShoFlex];
      const Vector3d upper =
          AngleAxisd(side * abd, Vector3d::UnitX()) * (AngleAxisd(-flex, Vector3d::UnitY()) * -up);
      const Vector3d axis = upper.cross(Vector3d(1, 0, 0.5)).normalized();
      const Vector3d fore = AngleAxisd(q[left ? kLElbow : kRElbow], axis) * upper;
      const Vector3d elb = sho + torso * upper * bone(s, 5);
      const Vector3d hand = elb + torso * fore * bone(s, 7);
      at(left ? Joint::LSho : Joint::RSho) = sho;
      at(left ? Joint::LElb : Joint::RElb) = elb;
      at(left ? Joint::LHand : Joint::RHand) = hand;
      at(left ? Joint::LFTip : Joint::RFTip) = hand + torso * fore * bone(s, 9);

      const Vector3d hip = yaw * Vector3d(0, side * 0.67, -0.74).normalized() * bone(s, 14);
      const double hflex = q[left ? kLHipFlex : kRHipFlex], habd = q[left ? kLHipAbd : kRHipAbd];
      const double knee = q[left ? kLKnee : kRKnee], ankle = q[left ? kLAnkle : kRAnkle];
      const Matrix3d abd_rot(AngleAxisd(side * habd, Vector3d::UnitX()));
      const Vector3d thigh = abd_rot * (AngleAxisd(-hflex, Vector3d::UnitY()) * -up);
      const Vector3d shank = abd_rot * (AngleAxisd(-(hflex - knee), Vector3d::UnitY()) * -up);
      const Vector3d foot = abd_rot * (AngleAxisd(-(hflex - knee + ankle), Vector3d::UnitY()) *
                                       Vector3d(0.94, 0, -0.34).normalized());
      const Vector3d kne = hip + yaw * thigh * bone(s, 16);
      const Vector3d ank = kne + yaw * shank * bone(s, 18);
      const Vector3d ball = ank + yaw * foot * bone(s, 20);
      at(left ? Joint::LHip : Joint::RHip) = hip;
      at(left ? Joint::LKne : Joint::RKne) = kne;
      at(left ? Joint::LAnk : Joint::RAnk) = ank;
      at(left ? Joint::LFoot : Joint::RFoot) = ball;
      at(left ? Joint::LToe : Joint::RToe) =
          ball + yaw * Vector3d(foot.x(), foot.y(), 0).normalized() * bone(s, 22);
    }
    const double z = grounded ? q[kLift] - lowest_sole(out) : 0.0;
    for (auto& p : out) p += Vector3d(q[kX], q[kY], z);
  }

  double stature() const { return shape_.stature_mm; }

 private:
  double lowest_sole(const JointPositions& p) const {
    double z = std::numeric_limits<double>::infinity();
    for (Joint j : {Joint::LAnk, Joint::RAnk, Joint::LFoot, Joint::RFoot, Joint::LToe, Joint::RToe})
      z = std::min(z, p[static_cast<size_t>(index(j))].z() - shape_.sole_radius_mm(j));
    return z;
  }
  BodyShape shape_;
  double scale_ = 1;
};

double smooth(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// Keyframed cycle: poses at phase u in [0, 1), smoothly blended, wrapping around.
Pose keyframes(const std::vector<std::pair<double, Pose>>& keys, double u) {
  u -= std::floor(u);
  for (size_t i = 0; i < keys.size(); ++i) {
    const auto& [u0, p0] = keys[i];
    const bool last = i + 1 == keys.size();
    const double u1 = last ? 1.0 + keys[0].first : keys[i + 1].first;
    const Pose& p1 = last ? keys[0].second : keys[i + 1].second;
    if (u >= u0 && u < u1) {
      const double w = smooth((u - u0) / (u1 - u0));
      Pose out;
      for (int k = 0; k < kCount; ++k) out[k] = (1 - w) * p0[k] + w * p1[k];
      return out;
    }
  }
  return keys[0].second;
}

class ProceduralMotion final : public Motion {
 public:
  using Driver = std::function<Pose(double t)>;
  ProceduralMotion(std::string name, double stature, double build, Eigen::Vector3d centre,
                   Driver driver)
      : Motion(std::move(name), stature),
        body_(stature, build),
        centre_(centre),
        driver_(std::move(driver)) {}
  double duration_s() const override { return std::numeric_limits<double>::infinity(); }
  void sample(double t_s, JointPositions& out) const override {
    Pose q = driver_(std::max(0.0, t_s));
    q[kX] += centre_.x();
    q[kY] += centre_.y();
    q[kLift] += centre_.z();
    body_.pose(q, out);
  }

 private:
  Body body_;
  Eigen::Vector3d centre_;
  Driver driver_;
};

Pose standing() {
  Pose q{};
  q[kLShoAbd] = q[kRShoAbd] = 0.15;
  q[kLElbow] = q[kRElbow] = 0.2;
  return q;
}

// Gait around a circle (so the subject stays in the capture volume): phase from cadence.
ProceduralMotion::Driver gait(double v_mm_s, double stride_mm, double radius_mm, double leg_mm,
                              bool run, double stature) {
  const double amp = std::asin(std::min(0.9, 0.5 * stride_mm / leg_mm)) * (run ? 1.0 : 0.9);
  return [=](double t) {
    const double phi = M_PI * v_mm_s / stride_mm * t;  // one gait cycle = two steps
    const double theta = v_mm_s * t / radius_mm;
    Pose q{};
    q[kX] = radius_mm * std::cos(theta);
    q[kY] = radius_mm * std::sin(theta);
    q[kYaw] = theta + M_PI / 2;
    q[kLean] = run ? 0.18 : 0.05;
    q[kTwist] = 0.08 * std::sin(phi);
    for (int side : {0, 1}) {
      const double ph = phi + side * M_PI;
      const double swing = std::pow(std::max(0.0, std::cos(ph)), 2);
      q[side ? kRHipFlex : kLHipFlex] = amp * std::sin(ph) + (run ? 0.25 : 0.0);
      q[side ? kRKnee : kLKnee] = (run ? 0.35 : 0.12) + (run ? 1.6 : 0.9) * swing;
      q[side ? kRAnkle : kLAnkle] = 0.15 * std::sin(ph);
      q[side ? kRShoFlex : kLShoFlex] = -0.9 * amp * std::sin(ph);
      q[side ? kRShoAbd : kLShoAbd] = 0.12;
      q[side ? kRElbow : kLElbow] = run ? 1.5 : 0.25 + 0.2 * swing;
    }
    if (run) q[kLift] = 0.035 * stature * std::max(0.0, std::sin(2 * phi));
    return q;
  };
}

}  // namespace

const std::vector<std::string>& builtin_motion_names() {
  static const std::vector<std::string> names = {"walk", "run",  "jump", "crouch",
                                                 "turn", "wave", "tpose"};
  return names;
}

std::unique_ptr<Motion> make_builtin_motion(const std::string& name, const MotionOptions& o) {
  HULLPOSE_THROW_UNLESS(o.stature_mm >= 800 && o.stature_mm <= 2300,
                        "stature " << o.stature_mm << " mm is outside 800..2300 mm");
  HULLPOSE_THROW_UNLESS(o.speed > 0 && o.speed <= 5, "speed " << o.speed << " must be in (0, 5]");
  HULLPOSE_THROW_UNLESS(o.stride_mm >= 0 && o.stride_mm <= 2500,
                        "stride " << o.stride_mm << " mm is out of range");
  const double s = o.stature_mm / 1750.0;
  const double leg = (0.224 + 0.239) * o.stature_mm;
  const double sp = o.speed;
  ProceduralMotion::Driver d;
  if (name == "walk") {
    d = gait(1300 * s * sp, o.stride_mm > 0 ? o.stride_mm : 720 * s, 700, leg, false, o.stature_mm);
  } else if (name == "run") {
    d = gait(2600 * s * sp, o.stride_mm > 0 ? o.stride_mm : 1300 * s, 650, leg, true, o.stature_mm);
  } else if (name == "tpose") {
    d = [](double) {
      Pose q{};
      q[kLShoAbd] = q[kRShoAbd] = M_PI / 2;
      return q;
    };
  } else if (name == "jump") {
    Pose stand = standing(), crouch = stand, flight = stand, land = stand;
    for (auto [hip, knee, ankle] :
         {std::tuple{kLHipFlex, kLKnee, kLAnkle}, std::tuple{kRHipFlex, kRKnee, kRAnkle}}) {
      crouch[hip] = 1.0, crouch[knee] = 1.5, crouch[ankle] = 0.5;
      land[hip] = 0.5, land[knee] = 0.8, land[ankle] = 0.3;
      flight[knee] = 0.15, flight[ankle] = -0.4;
    }
    crouch[kLean] = 0.5, land[kLean] = 0.25;
    crouch[kLShoFlex] = crouch[kRShoFlex] = -0.7;
    flight[kLShoFlex] = flight[kRShoFlex] = 1.7;
    flight[kLift] = o.stride_mm > 0 ? o.stride_mm : 250 * s;  // jump height
    const std::vector<std::pair<double, Pose>> keys = {{0.0, stand},  {0.3, crouch}, {0.45, stand},
                                                       {0.6, flight}, {0.75, stand}, {0.85, land}};
    d = [keys, sp](double t) { return keyframes(keys, t * sp / 1.6); };
  } else if (name == "crouch") {
    Pose stand = standing(), low = stand;
    for (auto [hip, knee, ankle] :
         {std::tuple{kLHipFlex, kLKnee, kLAnkle}, std::tuple{kRHipFlex, kRKnee, kRAnkle}})
      low[hip] = 1.7, low[knee] = 2.2, low[ankle] = 0.5;
    low[kLean] = 0.55;
    low[kLShoFlex] = low[kRShoFlex] = 1.3;
    low[kLElbow] = low[kRElbow] = 0.4;
    d = [keys =
             std::vector<std::pair<double, Pose>>{
                 {0.0, stand}, {0.15, stand}, {0.5, low}, {0.65, low}},
         sp](double t) { return keyframes(keys, t * sp / 3.0); };
  } else if (name == "turn") {
    d = [sp](double t) {
      Pose q{};
      q[kYaw] = 2 * M_PI * 0.5 * sp * t;  // pirouette on the left leg, half a turn per second
      q[kRHipFlex] = 1.2, q[kRHipAbd] = 0.5, q[kRKnee] = 2.0, q[kRAnkle] = -0.3;
      q[kLShoFlex] = q[kRShoFlex] = 1.2;
      q[kLShoAbd] = q[kRShoAbd] = 0.35;
      q[kLElbow] = q[kRElbow] = 0.9;
      return q;
    };
  } else if (name == "wave") {
    d = [sp](double t) {
      Pose q = standing();
      const double w = 2 * M_PI * 0.8 * sp * t;
      q[kYaw] = 0.35 * std::sin(2 * M_PI * 0.05 * t);
      q[kLShoAbd] = 1.6 + 0.9 * std::sin(w);
      q[kRShoAbd] = 1.6 + 0.9 * std::sin(w + M_PI);
      q[kLElbow] = 0.5 + 0.4 * std::sin(2 * w);
      q[kRElbow] = 0.5 + 0.4 * std::cos(2 * w);
      return q;
    };
  } else {
    std::string list;
    for (const auto& n : builtin_motion_names()) list += (list.empty() ? "" : ", ") + n;
    HULLPOSE_THROW("unknown motion '" << name << "' (built-in motions: " << list
                                      << "; or a .bvh file)");
  }
  return std::make_unique<ProceduralMotion>(name, o.stature_mm, o.build, o.centre_mm, std::move(d));
}

}  // namespace hullpose::synth
