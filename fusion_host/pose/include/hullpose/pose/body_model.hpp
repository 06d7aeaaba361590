#pragma once
// The subject's body: bone lengths and limb radii (capsules around the 24 bones of
// common/joints.hpp), estimated online from confident frames (BodyModelEstimator), used by the
// hull tracker (hull_tracker.hpp). No allocation.
#include <Eigen/Core>
#include <array>

#include "hullpose/common/dataset.hpp"
#include "hullpose/common/joints.hpp"

namespace hullpose::pose {

// The trunk's axial rotation: the signed angle (radians, right-handed about the spine's up
// direction LBack -> Chest) from the hip line (RHip -> LHip) to the shoulder line (RSho -> LSho),
// both projected on the plane across the spine. 0 when either line lies along the spine.
double torso_twist(const JointPositions& joints);
// Exchanges the left and right arms (shoulder to finger tip): same positions, labels swapped.
void swap_arms(JointPositions& joints);
// Turns the head (HeadTop about Head, its length kept) towards the trunk's axis (LBack -> Chest):
// its direction becomes the unit mean of its own, weighted 1 - trunk_weight, and the trunk's
// (unchanged where that mean vanishes or either direction is undefined).
void lean_head_on_trunk(JointPositions& joints, double trunk_weight);

struct BodyModel {
  std::array<double, kNumBones> length_mm{};
  std::array<double, kNumBones> radius_mm{};

  // Table 6.7's bone ratios and the prior radius ratios below, scaled to `stature_mm`.
  static BodyModel from_stature(double stature_mm);
  // The least-squares stature of the bone lengths under Table 6.7's ratios (the eval's
  // stature_from_joints applied to the model).
  double stature_mm() const;
};

// Capsule radius of each bone in statures before any frame is measured: half the typical
// adult girth of the segment (neck ~380 mm, head ~560 mm, upper arm ~300 mm, forearm ~250 mm,
// chest ~950 mm, thigh ~550 mm, calf ~370 mm at 1750 mm stature) divided by 2 pi. Only a
// starting point: the estimator replaces them with the radii the hull shows, which are larger
// (a visual hull is a superset of the body).
double prior_radius_ratio(int bone);

// A bone's capsule axis. Terminal bones end at the body's surface (crown, finger tip, toe tip),
// not inside it: their axis stops one radius short of the end joint, so the cap reaches it.
bool is_terminal(int bone);
// The end of the capsule axis of `bone` from `parent` towards `child` (radius `r`).
Eigen::Vector3d capsule_end(int bone, const Eigen::Vector3d& parent, const Eigen::Vector3d& child,
                            double r);

// Gives every bone of `joints` exactly `length_mm`, root (Chest) outward: each child is placed at
// its length from its already placed parent along the bone's direction in `joints` as given.
// A smoothed or otherwise edited pose keeps its bone directions and gets the model's lengths.
// A zero-length bone keeps its child on the parent.
void impose_bone_lengths(JointPositions& joints, const std::array<double, kNumBones>& length_mm);

// The model standing upright with its soles at height `sole_z` (mm; the floor is z = 0,
// docs/conventions.md), its pelvis over `xy`, facing `yaw` (radians from +x towards +y), legs
// straight, arms straight and raised sideways `arm_rad` from hanging (the default, ~6 degrees,
// hangs them clear of the trunk; pi/2 is a T-pose): where an acquisition from the hull alone
// starts (HullPoseEstimator).
inline constexpr double kHangingArmRad = 0.1;
JointPositions standing_pose(const BodyModel& model, const Eigen::Vector2d& xy, double yaw,
                             double sole_z = 0, double arm_rad = kHangingArmRad);

// One frame's Gauss-Newton evidence on the 24 bone lengths: the normal equations (hessian =
// sum of w J J^T, gradient = sum of w r J) of the fit's residuals r in both directions (the
// robust distances of the hull's surface points to their capsules, and of the capsule axis
// samples the hull rules out to the nearest surface point), J = dr/dlength with the pose's joint
// directions held (a longer bone moves everything beyond it along itself), linearised at the
// lengths `at_mm`, the pose's translation eliminated. A straight limb shows only its total length
// (at the cap), a bent one the split: the hessian says what a frame measures, so frames that show
// nothing about a bone do not dilute those that do (a running mean of per-frame lengths would pull
// everything to the prior).
struct LengthEvidence {
  using Matrix = Eigen::Matrix<double, kNumBones, kNumBones>;
  using Vector = Eigen::Matrix<double, kNumBones, 1>;
  Matrix hessian = Matrix::Zero();
  Vector gradient = Vector::Zero();
  std::array<double, kNumBones> at_mm{};
  bool measured = false;
};

struct BodyModelParams {
  // Confident frames averaged with equal weight, after which the bone lengths are held (locked:
  // every later frame is published with exactly these lengths, model version 1). 60 = 2 s at
  // 30 fps, "converging within the first seconds".
  int converge_frames = 60;
  // A subject seen in few confident frames still gets a held model: once this many frames were
  // tracked since the model started (3 s at 30 fps) it is held with what it has, if at least
  // min_hold_frames of them were confident (10 = the bottom-up stature's settling count).
  int hold_after_frames = 90;  // 3 s
  int min_hold_frames = 10;
  // Radii are not published and do not change bone lengths: after the hold each confident frame
  // still moves them by 1/radius_refine_frames (20 s: a bad frame cannot pull them far).
  int radius_refine_frames = 600;
  // The lengths' prior (Table 6.7 at the bottom-up stature) weighs as much as this many surface
  // points at a bone's cap: about what one frame shows of a well-seen extremity (~30 of the 1000
  // sampled points), so 60 frames of evidence outweigh it 60:1 where the hull shows a length and
  // it holds where the hull shows none (a limb never bent: its split stays Table 6.7's).
  // That weight is for a bone of prior_reference_ratio statures (0.1: the mean of Table 6.7's
  // 24 ratios); a bone of ratio q weighs (0.1 / q)^2 as much: the same stiffness per cent of its
  // length.
  double length_prior_points = 30;
  double prior_reference_ratio = 0.1;
  // A bone length or a radius may leave its prior by at most these factors. Bone lengths: the
  // CMU subjects' forearms are 0.7 of Table 6.7's and their upper arms 1.2; beyond 0.6..1.5 the
  // measurement, not the body, is wrong.
  double min_scale = 0.6, max_scale = 1.5;
  double min_radius_factor = 0.6, max_radius_factor = 2.5;
};

// Estimate of the subject's model: bone length scales (relative to Table 6.7 at the reference
// stature) and radii, each a running mean of per-frame measurements, left and right bones of a
// pair averaged (one body). Two states: converging (version() == 0, the lengths change with
// every confident frame: what is published meanwhile is provisional) and held (version() >= 1:
// the lengths never change again; reset() is refused while held, so a re-acquisition of the
// same subject keeps them).
class BodyModelEstimator {
 public:
  explicit BodyModelEstimator(BodyModelParams params = {});
  // Starts converging from Table 6.7 at this stature. No effect once held.
  void reset(double reference_stature_mm);
  bool started() const { return reference_mm_ > 0; }
  bool held() const { return version_ > 0; }
  // skeleton_t::model_version: 0 while converging, 1 once held.
  int version() const { return version_; }
  // One confident frame's measurements: the length evidence (lengths are the solution of all
  // the evidence so far and the prior; ignored once held) and each bone's mean surface distance
  // (mm, NaN where not measured).
  void add(const LengthEvidence& lengths, const std::array<double, kNumBones>& radius_mm);
  // One tracked frame, confident or not (the hold_after_frames clock).
  void tick();
  const BodyModel& model() const { return model_; }
  int frames() const { return frames_; }

 private:
  void rebuild();
  BodyModelParams params_;
  double reference_mm_ = 0;
  std::array<double, kNumBones> scale_{};
  // Sum of the frames' evidence, in the shared (left = right) lengths: hessian, and
  // hessian * at - gradient (so the minimiser is (A + prior)^-1 (b + prior * prior_length)).
  LengthEvidence::Matrix evidence_a_ = LengthEvidence::Matrix::Zero();
  LengthEvidence::Vector evidence_b_ = LengthEvidence::Vector::Zero();
  std::array<double, kNumBones> radius_{};
  std::array<int, kNumBones> radius_n_{};
  int frames_ = 0, ticks_ = 0, version_ = 0;
  BodyModel model_;
};

}  // namespace hullpose::pose
