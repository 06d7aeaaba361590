#include "hullpose/pose/model_fit.hpp"

#include <algorithm>
#include <cmath>

#include "hullpose/pose/anthropometry.hpp"

namespace hullpose::pose {
namespace {

// Rest-pose directions of the two bones that leave the skeleton curve, in (lateral, forward,
// up) unit components, from the CMU skeletons the model ratios come from (LeftArm offset from
// Spine1, LeftUpLeg offset from Hips): the shoulder is level and lateral, the hip joint sits
// lateral, a little forward and below the lower back.
constexpr double kShoulderLateral = 0.978;
constexpr double kHipLateral = 0.643, kHipForward = 0.295, kHipDown = 0.707;

double bone_between(Joint a, Joint b) {
  for (const Bone& bone : kBones)
    if ((bone.parent == a && bone.child == b) || (bone.parent == b && bone.child == a))
      return bone.stature_ratio;
  return 0;
}

// The right-side twin of a left joint (common's mirror() goes through names and allocates).
Joint side(Joint left_joint, bool right) {
  if (!right) return left_joint;
  switch (left_joint) {
    case Joint::LSho:
      return Joint::RSho;
    case Joint::LElb:
      return Joint::RElb;
    case Joint::LHand:
      return Joint::RHand;
    case Joint::LFTip:
      return Joint::RFTip;
    case Joint::LHip:
      return Joint::RHip;
    case Joint::LKne:
      return Joint::RKne;
    case Joint::LAnk:
      return Joint::RAnk;
    case Joint::LFoot:
      return Joint::RFoot;
    case Joint::LToe:
      return Joint::RToe;
    default:
      return left_joint;
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// SHAKE

Shake::Shake() {
  inv_mass_.fill(1.0);
}

void Shake::set_bone_lengths(const std::array<double, kNumBones>& lengths_mm) {
  length_ = lengths_mm;
}

void Shake::set_mass(Joint j, double mass) {
  inv_mass_[index(j)] = 1.0 / mass;
}

void Shake::clear_targets() {
  target_count_.fill(0);
}

void Shake::add_line(Joint j, const Line& line, double weight) {
  int& n = target_count_[index(j)];
  if (n == kMaxTargets) return;  // the fitter adds at most three per joint
  target_[index(j)][n++] = {line, false, weight};
}

void Shake::add_point(Joint j, const Eigen::Vector3d& point, double weight) {
  int& n = target_count_[index(j)];
  if (n == kMaxTargets) return;
  Line at;
  at.point = point;
  target_[index(j)][n++] = {at, true, weight};
}

double Shake::target_distance(Joint j, const Eigen::Vector3d& p) const {
  const int n = target_count_[index(j)];
  double sum = 0, weights = 0;
  for (int k = 0; k < n; ++k) {
    const Target& t = target_[index(j)][k];
    sum += t.weight * (t.is_point ? (p - t.line.point).norm() : t.line.distance(p));
    weights += t.weight;
  }
  return weights > 0 ? sum / weights : 0;
}

// One Gauss-Seidel sweep of algorithm 1 over all bones.
template <bool kMeasure>
bool Shake::sweep_bones(JointPositions& x, const std::array<Eigen::Vector3d, kNumBones>& reference,
                        const std::array<std::array<double, 2>, kNumBones>* within) const {
  bool all_within = true;
  for (int b = 0; b < kNumBones; ++b) {
    const int p = index(kBones[b].parent), c = index(kBones[b].child);
    const Eigen::Vector3d r = x[p] - x[c];
    const double l = length_[b];
    const double r2 = r.squaredNorm();
    const double sigma = r2 - l * l;  // the holonomic constraint, eq. 1
    if constexpr (kMeasure) all_within = all_within && r2 > (*within)[b][0] && r2 < (*within)[b][1];
    // Lagrange factor from sigma'' = 0 to first order; the reference vector is the bone before
    // this iteration's unconstrained move, unless that move turned it by more than ~60 degrees
    // (cos < 1/2, compared squared: no square root per bone and sweep).
    Eigen::Vector3d ref = reference[b];
    const double along = ref.dot(r);
    if (along < 0 || along * along < 0.25 * ref.squaredNorm() * r2) ref = r;
    const double denom = 2 * (inv_mass_[p] + inv_mass_[c]) * ref.dot(r);
    if (std::abs(denom) < 1e-12) continue;
    const double a = sigma / denom;
    x[p] -= a * inv_mass_[p] * ref;
    x[c] += a * inv_mass_[c] * ref;
  }
  return all_within;
}

Shake::Result Shake::solve(JointPositions& x, const ShakeParams& params) const {
  Result result;
  std::array<Eigen::Vector3d, kNumBones> reference;
  auto take_reference = [&] {
    for (int b = 0; b < kNumBones; ++b)
      reference[b] = x[index(kBones[b].parent)] - x[index(kBones[b].child)];
  };
  for (int it = 0; it < params.max_iterations; ++it) {
    take_reference();
    const JointPositions before = x;
    // Unconstrained move: each pseudo-constraint's dummy body (infinite mass) pulls its joint a
    // fraction of the way to the line or point. Paper 6 sets the dummy bond to rho*v; choosing
    // rho per step so the move is a fixed fraction of the normal distance cannot overshoot.
    for (int j = 0; j < kNumJoints; ++j) {
      const int n = target_count_[j];
      if (n == 0) continue;
      Eigen::Vector3d pull = Eigen::Vector3d::Zero();
      double weights = 0;
      for (int k = 0; k < n; ++k) {
        const Target& t = target_[j][k];
        pull += t.weight * ((t.is_point ? t.line.point : t.line.project(x[j])) - x[j]);
        weights += t.weight;
      }
      x[j] += params.target_gain * pull / weights;
    }
    // A few sweeps per step are enough: the next step starts from nearly rigid bones, and the
    // final pass below makes them exact.
    for (int s = 0; s < params.sweeps_per_iteration; ++s) sweep_bones<false>(x, reference, nullptr);
    result.iterations = it + 1;
    // Converged when the pose settles: the pseudo-constraints pull against each other and
    // against the bones, so their pulls never vanish, but the equilibrium stops moving.
    double moved = 0;
    for (int j = 0; j < kNumJoints; ++j) moved = std::max(moved, (x[j] - before[j]).norm());
    if (moved < params.tolerance_mm) break;
  }
  // Bones exactly to length at the end, whatever the pseudo-constraints did.
  // |length - l| < tolerance as squared lengths: no square root per bone and sweep.
  std::array<std::array<double, 2>, kNumBones> within;
  for (int b = 0; b < kNumBones; ++b) {
    const double lo = std::max(0.0, length_[b] - params.bone_tolerance_mm);
    within[b] = {lo * lo,
                 (length_[b] + params.bone_tolerance_mm) * (length_[b] + params.bone_tolerance_mm)};
  }
  result.max_bone_error_mm = 0;
  for (int s = 0; s < params.max_bone_sweeps * params.final_sweep_factor; ++s) {
    take_reference();
    if (sweep_bones<true>(x, reference, &within)) break;
  }
  for (int b = 0; b < kNumBones; ++b) {
    const double l = (x[index(kBones[b].parent)] - x[index(kBones[b].child)]).norm();
    result.max_bone_error_mm = std::max(result.max_bone_error_mm, std::abs(l - length_[b]));
  }
  double sum = 0;
  int n = 0;
  for (int j = 0; j < kNumJoints; ++j)
    if (target_count_[j] > 0) {
      sum += target_distance(static_cast<Joint>(j), x[j]);
      ++n;
    }
  result.mean_target_distance_mm = n > 0 ? sum / n : 0;
  return result;
}

// ---------------------------------------------------------------------------------------------
// Model fitting

ModelFitter::ModelFitter(FitParams params) : params_(params) {
  // The tips are where the skeleton is most reliable: heavier, so bone corrections move the
  // inner joints rather than pulling the tips off their points.
  for (Joint j : {Joint::HeadTop, Joint::LFTip, Joint::RFTip, Joint::LToe, Joint::RToe})
    shake_.set_mass(j, params_.tip_mass);
}

void ModelFitter::compute_arcs(const LabelledTree& tree, const std::vector<int32_t>& path) const {
  arc_.resize(path.size());
  double a = 0;
  for (size_t k = 0; k < path.size(); ++k) {
    if (k > 0) a += (tree.position[path[k]] - tree.position[path[k - 1]]).norm();
    arc_[k] = a;
  }
}

// Point at arc length `arc_mm` along the path (arcs from compute_arcs); beyond either end the
// path is extended straight along its last few voxels.
Eigen::Vector3d ModelFitter::at_arc(const LabelledTree& tree, const std::vector<int32_t>& path,
                                    double arc_mm) const {
  const size_t n = path.size();
  const double total = arc_.back();
  const double span = std::min(total, 3 * tree.voxel_mm);
  auto interpolate = [&](double a) {
    const size_t k =
        static_cast<size_t>(std::upper_bound(arc_.begin(), arc_.end(), a) - arc_.begin());
    if (k == 0) return tree.position[path.front()];
    if (k >= n) return tree.position[path.back()];
    const double t = (a - arc_[k - 1]) / std::max(1e-9, arc_[k] - arc_[k - 1]);
    return Eigen::Vector3d(tree.position[path[k - 1]] +
                           t * (tree.position[path[k]] - tree.position[path[k - 1]]));
  };
  if (n == 1 || span <= 0) return tree.position[path.front()];
  if (arc_mm < 0) {
    // Beyond the tip: along the chord of a stretch at least twice the extension, so a long
    // extension (the head) follows the limb rather than the last voxels' noise.
    const double back = std::min(total, std::max(span, -2 * arc_mm));
    const Eigen::Vector3d d = (tree.position[path.front()] - interpolate(back)).normalized();
    return tree.position[path.front()] + d * -arc_mm;
  }
  if (arc_mm > total) {
    const Eigen::Vector3d d = (tree.position[path.back()] - interpolate(total - span)).normalized();
    return tree.position[path.back()] + d * (arc_mm - total);
  }
  return interpolate(arc_mm);
}

bool ModelFitter::group_line(const LabelledTree& tree, const std::vector<int32_t>& path,
                             double from_mm, double to_mm, Line& line) const {
  MomentAccumulator m;
  Eigen::Vector3d first = Eigen::Vector3d::Zero(), last = first;
  for (size_t k = 0; k < path.size(); ++k) {
    if (arc_[k] < from_mm || arc_[k] > to_mm) continue;
    if (m.count() == 0) first = tree.position[path[k]];
    last = tree.position[path[k]];
    m.add(tree.position[path[k]]);
  }
  if (m.count() < 3 || (last - first).norm() < params_.min_group_voxels * tree.voxel_mm)
    return false;
  line = fit_line(m);
  return true;
}

double ModelFitter::chord_sum(const LabelledTree& tree, const std::vector<int32_t>& path,
                              std::span<const double> groups_mm, double start_mm) const {
  compute_arcs(tree, path);
  double sum = 0, a = start_mm;
  Eigen::Vector3d prev = at_arc(tree, path, a);
  for (double g : groups_mm) {
    a = std::min(a + g, arc_.back());
    const Eigen::Vector3d p = at_arc(tree, path, a);
    sum += (p - prev).norm();
    prev = p;
  }
  if (a < arc_.back()) sum += (tree.position[path.back()] - prev).norm();
  return sum;
}

double ModelFitter::frame_stature(const LabelledTree& tree) const {
  // Paper 6: node groups per bone from the toe tip up to the head top, chord lengths summed.
  // The arms are measured the same way and added (fingertip to origin is ratio::kArmChain
  // statures): twice the data for the scale that every bone of the model depends on. The
  // groups need bone lengths, which need the stature: start from the paper-5 reference length
  // and refine (group boundaries off the joints make chords cut the corners).
  double stature = tree.longest_path_mm / ratio::kLongestPath;
  const auto& p = tree.limb_path;
  auto path = [&](Extremity e) -> const std::vector<int32_t>& { return p[static_cast<int>(e)]; };
  for (int pass = 0; pass < 3; ++pass) {
    const double s = stature;
    const std::array<double, 4> leg = {bone_ratio(Joint::LToe) * s, bone_ratio(Joint::LFoot) * s,
                                       bone_ratio(Joint::LAnk) * s, bone_ratio(Joint::LKne) * s};
    const std::array<double, 3> torso = {bone_ratio(Joint::UBack) * s, bone_ratio(Joint::Back) * s,
                                         bone_ratio(Joint::LBack) * s};
    const std::array<double, 3> head = {bone_ratio(Joint::HeadTop) * s, bone_ratio(Joint::Head) * s,
                                        bone_ratio(Joint::Neck) * s};
    const std::array<double, 3> arm = {bone_ratio(Joint::LFTip) * s, bone_ratio(Joint::LHand) * s,
                                       bone_ratio(Joint::LElb) * s};
    const double legs =
        0.5 * (chord_sum(tree, path(Extremity::LFoot), leg, -params_.foot_end_ratio * s) +
               chord_sum(tree, path(Extremity::RFoot), leg, -params_.foot_end_ratio * s));
    const double arms =
        0.5 * (chord_sum(tree, path(Extremity::LHand), arm, -params_.hand_end_ratio * s) +
               chord_sum(tree, path(Extremity::RHand), arm, -params_.hand_end_ratio * s));
    const double body = legs + chord_sum(tree, tree.torso_path, torso, 0) +
                        chord_sum(tree, path(Extremity::Head), head, -params_.head_end_ratio * s);
    stature = (body + arms) / (ratio::kStaturePath + ratio::kArmChain);
  }
  return stature;
}

void ModelFitter::fit_chain(const LabelledTree& tree, const std::vector<int32_t>& path,
                            std::span<const Joint> joints, double end_offset_mm,
                            bool point_at_tip) {
  compute_arcs(tree, path);
  const double margin = 0.5 * tree.voxel_mm;
  double a = -end_offset_mm;
  for (size_t k = 0; k < joints.size(); ++k) {
    result_.joints[index(joints[k])] = at_arc(tree, path, a);
    if (k + 1 == joints.size()) break;
    const double next = a + bone_between(joints[k], joints[k + 1]) * stature_;
    Line line;
    if (group_line(tree, path, a - margin, next + margin, line)) {
      shake_.add_line(joints[k], line);
      shake_.add_line(joints[k + 1], line);
    }
    a = next;
  }
  if (point_at_tip)
    shake_.add_point(joints[0], result_.joints[index(joints[0])], params_.tip_weight);
}

const FitResult& ModelFitter::fit(const LabelledTree& tree, double stature_mm) {
  stature_ = stature_mm;
  result_.ok = false;
  std::array<double, kNumBones> lengths;
  for (int b = 0; b < kNumBones; ++b) lengths[b] = kBones[b].stature_ratio * stature_mm;
  shake_.set_bone_lengths(lengths);
  shake_.clear_targets();
  const auto& paths = tree.limb_path;
  const int head = static_cast<int>(Extremity::Head);

  // Rough alignment and lines: every joint starts at its arc position along its labelled path
  // (the chest at the origin, the model oriented by the tree's paths and forward vector).
  static constexpr std::array<Joint, 4> kNeck = {Joint::HeadTop, Joint::Head, Joint::Neck,
                                                 Joint::Chest};
  fit_chain(tree, paths[head], kNeck, params_.head_end_ratio * stature_mm, true);
  for (bool right : {false, true}) {
    const std::array<Joint, 4> arm = {side(Joint::LFTip, right), side(Joint::LHand, right),
                                      side(Joint::LElb, right), side(Joint::LSho, right)};
    const std::array<Joint, 5> leg = {side(Joint::LToe, right), side(Joint::LFoot, right),
                                      side(Joint::LAnk, right), side(Joint::LKne, right),
                                      side(Joint::LHip, right)};
    fit_chain(tree, paths[static_cast<int>(right ? Extremity::RHand : Extremity::LHand)], arm,
              params_.hand_end_ratio * stature_mm, true);
    fit_chain(tree, paths[static_cast<int>(right ? Extremity::RFoot : Extremity::LFoot)], leg,
              params_.foot_end_ratio * stature_mm, true);
  }
  static constexpr std::array<Joint, 4> kTorso = {Joint::Chest, Joint::UBack, Joint::Back,
                                                  Joint::LBack};
  fit_chain(tree, tree.torso_path, kTorso, 0, false);

  // Shoulders and hips: the skeleton is unreliable there (limbs close to the body shorten), so
  // their lines are the torso line displaced along the mediolateral axes (paper 6). The hip
  // axis comes from the tree's forward vector; the shoulder axis from a plane fitted to the
  // upper torso, which follows a twisted torso.
  MomentAccumulator torso_nodes, upper;
  for (int32_t i : tree.torso_path) torso_nodes.add(tree.position[i]);
  Line torso =
      torso_nodes.count() >= 2 ? fit_line(torso_nodes) : Line{tree.position[tree.origin], tree.up};
  if (torso.direction.dot(tree.up) < 0) torso.direction = -torso.direction;
  compute_arcs(tree, tree.torso_path);
  for (size_t k = 0;
       k < tree.torso_path.size() && arc_[k] <= params_.upper_torso_ratio * stature_mm; ++k)
    upper.add(tree.position[tree.torso_path[k]]);
  for (int s : {static_cast<int>(Extremity::LHand), static_cast<int>(Extremity::RHand)}) {
    const auto& p = paths[s];
    compute_arcs(tree, p);
    for (size_t k = 0; k < p.size(); ++k)
      if (arc_.back() - arc_[k] <= params_.shoulder_reach_ratio * stature_mm)
        upper.add(tree.position[p[k]]);
  }
  Eigen::Vector3d shoulder_axis = tree.left;
  if (upper.count() >= 4) {
    Eigen::Vector3d normal = fit_plane_normal(upper);
    if (normal.dot(tree.forward) < 0) normal = -normal;
    const Eigen::Vector3d axis = tree.up.cross(normal);
    if (axis.norm() > 0.5 && axis.normalized().dot(tree.left) > 0.5)
      shoulder_axis = axis.normalized();
  }
  const double sho = bone_ratio(Joint::LSho) * stature_mm,
               hip = bone_ratio(Joint::LHip) * stature_mm;
  for (bool right : {false, true}) {
    const double sign = right ? -1 : 1;
    Line sho_line = torso, hip_line = torso;
    sho_line.point += sign * kShoulderLateral * sho * shoulder_axis;
    hip_line.point += sign * kHipLateral * hip * tree.left + kHipForward * hip * tree.forward;
    // Weak: these lines are a guess from the torso, the limb lines and tips are measured.
    shake_.add_line(side(Joint::LSho, right), sho_line, params_.torso_offset_weight);
    shake_.add_line(side(Joint::LHip, right), hip_line, params_.torso_offset_weight);
    // The hip leaves the curve: start it at its rest offset from the lower back.
    result_.joints[index(side(Joint::LHip, right))] =
        result_.joints[index(Joint::LBack)] +
        hip * (sign * kHipLateral * tree.left + kHipForward * tree.forward - kHipDown * tree.up);
  }

  const Shake::Result r = shake_.solve(result_.joints, params_.shake);
  result_.iterations = r.iterations;
  result_.max_bone_error_mm = r.max_bone_error_mm;
  result_.mean_target_distance_mm = r.mean_target_distance_mm;

  // Confidence: the rank factor of the limb the joint belongs to, lowered by its distance to
  // its lines in voxels.
  auto limb_of = [&](Joint j) -> int {
    switch (j) {
      case Joint::LSho:
      case Joint::LElb:
      case Joint::LHand:
      case Joint::LFTip:
        return static_cast<int>(Extremity::LHand);
      case Joint::RSho:
      case Joint::RElb:
      case Joint::RHand:
      case Joint::RFTip:
        return static_cast<int>(Extremity::RHand);
      case Joint::LHip:
      case Joint::LKne:
      case Joint::LAnk:
      case Joint::LFoot:
      case Joint::LToe:
        return static_cast<int>(Extremity::LFoot);
      case Joint::RHip:
      case Joint::RKne:
      case Joint::RAnk:
      case Joint::RFoot:
      case Joint::RToe:
        return static_cast<int>(Extremity::RFoot);
      default:
        return head;
    }
  };
  bool finite = true;
  for (int j = 0; j < kNumJoints; ++j) {
    finite = finite && result_.joints[j].allFinite();
    const double d = shake_.target_distance(static_cast<Joint>(j), result_.joints[j]) /
                     std::max(1.0, tree.voxel_mm);
    result_.confidence[j] =
        static_cast<float>(tree.limb_score[limb_of(static_cast<Joint>(j))] / (1 + d));
  }
  result_.ok = finite && result_.max_bone_error_mm < params_.shake.max_bone_error_mm;
  return result_;
}

}  // namespace hullpose::pose
