// GCC 12 with -march=native reports false "uninitialized" warnings inside Eigen's AVX-512
// dense kernels (the length evidence's 24x24 products and LDLT); not ours to fix (as in
// tools/calibrate/src/bundle_adjust.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include "hullpose/pose/body_model.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace hullpose::pose {

double prior_radius_ratio(int bone) {
  // kBones order (common/joints.hpp); see the header for the girths behind these.
  static constexpr std::array<double, kNumBones> kRatio = {
      0.034, 0.034,                // neck
      0.050,                       // head
      0.045, 0.045,                // shoulders (the upper chest beside the neck)
      0.027, 0.027, 0.023, 0.023,  // upper and lower arms
      0.018, 0.018,                // hands
      0.075, 0.075, 0.075,         // thorax, upper and lower spine
      0.055, 0.055,                // hips (the pelvis)
      0.050, 0.050, 0.034, 0.034,  // thighs, lower legs
      0.025, 0.025, 0.020, 0.020,  // feet, toes
  };
  return kRatio[static_cast<size_t>(bone)];
}

bool is_terminal(int bone) {
  const Joint c = kBones[static_cast<size_t>(bone)].child;
  return c == Joint::HeadTop || c == Joint::LFTip || c == Joint::RFTip || c == Joint::LToe ||
         c == Joint::RToe;
}

Eigen::Vector3d capsule_end(int bone, const Eigen::Vector3d& parent, const Eigen::Vector3d& child,
                            double r) {
  if (!is_terminal(bone)) return child;
  const Eigen::Vector3d d = child - parent;
  const double len = d.norm();
  return len > r ? Eigen::Vector3d(child - d * (r / len)) : parent;
}

void impose_bone_lengths(JointPositions& joints, const std::array<double, kNumBones>& length_mm) {
  const JointPositions given = joints;
  for (int b = 0; b < kNumBones; ++b) {  // kBones lists parents before children
    const int p = index(kBones[b].parent), c = index(kBones[b].child);
    const Eigen::Vector3d d = given[c] - given[p];
    const double n = d.norm();
    joints[c] = n > 1e-9 ? Eigen::Vector3d(joints[p] + d * (length_mm[b] / n)) : joints[p];
  }
}

JointPositions standing_pose(const BodyModel& model, const Eigen::Vector2d& xy, double yaw,
                             double sole_z, double arm_rad) {
  // Each bone's direction from its parent joint, x forward, y to the subject's left, z up.
  auto direction = [arm_rad](Joint child) -> Eigen::Vector3d {
    switch (child) {
      case Joint::Neck:
      case Joint::Head:
      case Joint::HeadTop:
        return {0, 0, 1};
      case Joint::LSho:
      case Joint::RSho:
        return {0, 1, -0.25};  // the clavicles slope down to the shoulders
      case Joint::LElb:
      case Joint::RElb:
      case Joint::LHand:
      case Joint::RHand:
      case Joint::LFTip:
      case Joint::RFTip:
        return {0, std::sin(arm_rad), -std::cos(arm_rad)};
      case Joint::LHip:
      case Joint::RHip:
        return {0, 1, -0.8};
      case Joint::LFoot:
      case Joint::RFoot:
        return {1, 0, -0.6};  // ankle to the ball of the foot
      case Joint::LToe:
      case Joint::RToe:
        return {1, 0, 0};
      default:  // the spine from the chest down, the legs
        return {0, 0, -1};
    }
  };
  JointPositions p{};
  for (int b = 0; b < kNumBones; ++b) {  // kBones lists parents before children
    const Joint child = kBones[b].child;
    Eigen::Vector3d d = direction(child);
    for (Joint r : {Joint::RSho, Joint::RElb, Joint::RHand, Joint::RFTip, Joint::RHip, Joint::RKne,
                    Joint::RAnk, Joint::RFoot, Joint::RToe})
      if (child == r) d.y() = -d.y();
    p[index(child)] = p[index(kBones[b].parent)] + model.length_mm[b] * d.normalized();
  }
  // The soles: the lowest point of the foot and toe capsules.
  double sole = std::numeric_limits<double>::max();
  for (int b = 0; b < kNumBones; ++b) {
    const Joint c = kBones[b].child;
    if (c == Joint::LFoot || c == Joint::RFoot || c == Joint::LToe || c == Joint::RToe)
      sole = std::min(
          sole, std::min(p[index(kBones[b].parent)].z(), p[index(c)].z()) - model.radius_mm[b]);
  }
  const Eigen::Vector3d pelvis = p[index(Joint::LBack)];
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (Eigen::Vector3d& j : p)
    j = turn * Eigen::Vector3d(j.x() - pelvis.x(), j.y() - pelvis.y(), j.z() - sole) +
        Eigen::Vector3d(xy.x(), xy.y(), sole_z);
  return p;
}

double torso_twist(const JointPositions& joints) {
  const Eigen::Vector3d up = joints[index(Joint::Chest)] - joints[index(Joint::LBack)];
  if (up.squaredNorm() < 1e-12) return 0;
  const Eigen::Vector3d u = up.normalized();
  auto across = [&](Joint l, Joint r) {
    const Eigen::Vector3d d = joints[index(l)] - joints[index(r)];
    return Eigen::Vector3d(d - d.dot(u) * u);
  };
  const Eigen::Vector3d hips = across(Joint::LHip, Joint::RHip);
  const Eigen::Vector3d shoulders = across(Joint::LSho, Joint::RSho);
  if (hips.squaredNorm() < 1e-12 || shoulders.squaredNorm() < 1e-12) return 0;
  return std::atan2(hips.cross(shoulders).dot(u), hips.dot(shoulders));
}

void swap_arms(JointPositions& joints) {
  for (auto [l, r] : {std::pair{Joint::LSho, Joint::RSho}, std::pair{Joint::LElb, Joint::RElb},
                      std::pair{Joint::LHand, Joint::RHand}, std::pair{Joint::LFTip, Joint::RFTip}})
    std::swap(joints[index(l)], joints[index(r)]);
}

void lean_head_on_trunk(JointPositions& joints, double trunk_weight) {
  const Eigen::Vector3d& head = joints[index(Joint::Head)];
  const Eigen::Vector3d trunk = joints[index(Joint::Chest)] - joints[index(Joint::LBack)];
  Eigen::Vector3d& top = joints[index(Joint::HeadTop)];
  const double len = (top - head).norm();
  if (len < 1e-9 || trunk.norm() < 1e-9) return;
  const Eigen::Vector3d d =
      (1 - trunk_weight) * (top - head) / len + trunk_weight * trunk.normalized();
  if (d.norm() < 1e-9) return;
  top = head + len * d.normalized();
}

BodyModel BodyModel::from_stature(double stature_mm) {
  BodyModel m;
  for (int b = 0; b < kNumBones; ++b) {
    m.length_mm[b] = kBones[b].stature_ratio * stature_mm;
    m.radius_mm[b] = prior_radius_ratio(b) * stature_mm;
  }
  return m;
}

double BodyModel::stature_mm() const {
  double num = 0, den = 0;
  for (int b = 0; b < kNumBones; ++b) {
    num += kBones[b].stature_ratio * length_mm[b];
    den += kBones[b].stature_ratio * kBones[b].stature_ratio;
  }
  return num / den;
}

namespace {
// Left and right are one body: both bones of a pair share one estimate, kept at the left bone
// (kBones lists a pair's left bone first; neck, head and spine have no twin).
int shared_index(int bone) {
  const bool right_of_pair =
      (bone >= 4 && bone <= 10 && bone % 2 == 0) || (bone >= 15 && bone % 2 == 1);
  return right_of_pair ? bone - 1 : bone;
}
}  // namespace

BodyModelEstimator::BodyModelEstimator(BodyModelParams params) : params_(params) {}

void BodyModelEstimator::reset(double reference_stature_mm) {
  if (held()) return;
  reference_mm_ = reference_stature_mm;
  scale_.fill(1.0);
  evidence_a_.setZero();
  evidence_b_.setZero();
  for (int b = 0; b < kNumBones; ++b) radius_[b] = prior_radius_ratio(b) * reference_stature_mm;
  radius_n_.fill(0);
  frames_ = ticks_ = 0;
  rebuild();
}

void BodyModelEstimator::add(const LengthEvidence& lengths,
                             const std::array<double, kNumBones>& radius_mm) {
  if (!started()) return;
  ++frames_;
  if (!held() && lengths.measured) {
    for (int i = 0; i < kNumBones; ++i) {
      const int si = shared_index(i);
      double hl = 0;
      for (int j = 0; j < kNumBones; ++j) {
        evidence_a_(si, shared_index(j)) += lengths.hessian(i, j);
        hl += lengths.hessian(i, j) * lengths.at_mm[j];
      }
      evidence_b_(si) += hl - lengths.gradient(i);
    }
    LengthEvidence::Matrix m = evidence_a_;
    LengthEvidence::Vector rhs = evidence_b_;
    for (int b = 0; b < kNumBones; ++b) {
      const double prior_mm = kBones[b].stature_ratio * reference_mm_;
      // Right bones of a pair have no row of their own (their evidence is the left's): the
      // prior alone keeps the system regular there.
      // Relative: a short bone's prior is as stiff, per per cent of its length, as a long one's
      // (else the tips' caps, which show the chain's total, move the short end bones most).
      const double rel = params_.prior_reference_ratio / kBones[b].stature_ratio;
      m(b, b) += params_.length_prior_points * rel * rel;
      rhs(b) += params_.length_prior_points * rel * rel * prior_mm;
    }
    const LengthEvidence::Vector l = m.ldlt().solve(rhs);
    for (int b = 0; b < kNumBones; ++b)
      if (shared_index(b) == b)
        scale_[b] = std::clamp(l(b) / (kBones[b].stature_ratio * reference_mm_), params_.min_scale,
                               params_.max_scale);
  }
  // Radii: equal weights while converging (a running mean), then a fixed small rate.
  for (int b = 0; b < kNumBones; ++b) {
    if (!std::isfinite(radius_mm[b])) continue;
    const int s = shared_index(b);
    ++radius_n_[s];
    const double rate =
        1.0 /
        (radius_n_[s] <= params_.converge_frames ? radius_n_[s] : params_.radius_refine_frames);
    const double prior = prior_radius_ratio(b) * reference_mm_;
    radius_[s] += rate * (std::clamp(radius_mm[b], params_.min_radius_factor * prior,
                                     params_.max_radius_factor * prior) -
                          radius_[s]);
  }
  rebuild();
  if (frames_ >= params_.converge_frames) version_ = std::max(version_, 1);
}

void BodyModelEstimator::tick() {
  if (!started() || held()) return;
  if (++ticks_ >= params_.hold_after_frames && frames_ >= params_.min_hold_frames) version_ = 1;
}

void BodyModelEstimator::rebuild() {
  for (int b = 0; b < kNumBones; ++b) {
    if (!held())
      model_.length_mm[b] = kBones[b].stature_ratio * reference_mm_ * scale_[shared_index(b)];
    model_.radius_mm[b] = radius_[shared_index(b)];
  }
}

}  // namespace hullpose::pose
