#pragma once
// Model-to-hull tracking: the articulated 24-capsule body (body_model.hpp) fitted to the
// surface voxels of the carved hull, from the predicted pose (previous + velocity).
//
// Each iteration is one step of articulated ICP (as Horaud et al. 2009 do EM with ellipsoids on
// visual-hull points, here with capsules and hard assignment): every sampled surface point is
// assigned to the capsule whose surface is nearest, with a robust weight; the displacement that
// would put the point on that capsule's surface is shared between the bone's two joints by the
// point's position along the bone; the joints then move towards their targets under SHAKE's
// bone-length constraints (model_fit.hpp), with the prediction as a weak prior and the
// bottom-up extremities as point targets where they agree. The other direction, model to hull:
// every bone sample the hull rules out is pulled to the nearest surface point (the hull contains
// the body). A limb the hull shows no surface for (merged into the torso) is kept inside the
// hull near its predicted place and gets low confidence.
//
// Lifecycle: construct once; HullSurface::extract() and HullTracker::track() per frame. Fixed
// buffers (sized by TrackParams::max_points at construction): no allocation per frame.
#include <Eigen/Core>
#include <array>
#include <span>
#include <vector>

#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/pose/body_model.hpp"
#include "hullpose/pose/model_fit.hpp"

namespace hullpose::pose {

// The hull's surface voxels (set, with an unset 6-neighbour), evenly subsampled in scan order to
// at most `max_points`, as mm positions; plus what the hull rules out, for the fit and the
// scoring.
class HullSurface {
 public:
  explicit HullSurface(int max_points);
  // nullptr: no hull this frame (no points).
  void extract(const fusion::BitGrid* hull, const VoxelGridSpec& grid);
  std::span<const Eigen::Vector3f> points() const { return {points_.data(), count_}; }
  bool empty() const { return count_ == 0; }
  // Whether the hull reaches a side or the top of the grid (part of the body is outside).
  bool touches_edge() const { return touches_edge_; }
  // Whether the hull rules out a ball of radius_mm about `mm` lying inside the body: the nearest
  // voxel centre is unset and within the ball. No hull: everything is ruled out.
  bool excludes(const Eigen::Vector3d& mm, double radius_mm) const;
  // The point nearest to `mm` among points 0, stride, 2 stride, ... (the first of them on a tie).
  // Needs a point.
  Eigen::Vector3d nearest(const Eigen::Vector3d& mm, size_t stride) const;
  // Height (mm, z) of the top face of the highest hull voxel whose centre lies within radius_mm
  // of `xy` horizontally; NaN when there is none.
  double top_mm(const Eigen::Vector2d& xy, double radius_mm) const;
  double voxel_mm() const { return grid_.voxel_mm; }

 private:
  std::vector<Eigen::Vector3f> points_;
  size_t count_ = 0;
  // One grid word's surface voxels (x0: the word's first x).
  struct SurfaceWord {
    uint64_t bits;
    int x0, y, z;
  };
  std::vector<SurfaceWord> words_;  // the frame's non-empty surface words, sized to the grid
  bool touches_edge_ = false;
  const fusion::BitGrid* hull_ = nullptr;
  VoxelGridSpec grid_;
};

struct TrackParams {
  // Surface points per frame: ~1000 cover every limb of a person with tens of points at 64^3
  // and 128^3 (a forearm's surface is ~0.3 % of the body's... ~30 points) and keep one ICP
  // iteration near 50 us.
  int max_points = 1000;
  // ICP iterations at most; it stops early once no joint moves more than converged_voxels (a
  // tenth of a voxel: below what the hull can show).
  int iterations = 6;
  double converged_voxels = 0.1;
  int fine_iterations = 2;
  size_t coarse_stride = 3;
  // Robust weight 1 / (1 + (r / sigma)^2) of a point at distance r from its capsule's surface;
  // sigma = sigma_voxels voxels + sigma_mm (the hull's quantisation and its ghost volume).
  double sigma_voxels = 1.5;
  double sigma_mm = 20;
  // Points farther than this from every capsule (statures) are not the body's (ghosts, spurs).
  double gate_ratio = 0.12;
  // A joint's data target weighs support / (support + full_support_points): a joint pulled by a
  // few points moves little.
  double full_support_points = 8;
  // Every bone sample the hull rules out (HullSurface::excludes) pulls its bone towards the nearest
  // surface point with this weight (a surface point's is at most 1). 1: a limb with no points of
  // its own is moved by its samples as by as many points; where it has points, they decide. 0.9-1.1
  // gave the same figures within the tracker's run-to-run spread on the shared clips (make eval).
  double inside_weight = 1;
  // The shoulder girdle turns about the spine against the hips (torso_twist) by at most
  // max_twist_deg. The hull cannot hold it there: the chest's capsule is round about the spine,
  // so an arm's points drag its shoulder round the chest for free, and the arms end up on the
  // wrong sides (measured on the salsa clip 60_04: the girdle turned by up to 160 deg against the
  // hips; no subject of the shared clips passes 46). The spine's axial rotation, thoracic and
  // lumbar together, is about 45 deg in adults; 60 leaves room for the girdle's own travel.
  // Beyond it both shoulders are pulled back to it with twist_weight (a fully supported joint's
  // data weight is ~1). A twist beyond 90 deg is the arms' labels, not their positions, being
  // wrong (the hull cannot tell one arm from the other; anatomy can): the arms are swapped.
  // Measured and left out (no gain in make eval beyond the tracker's run-to-run spread): a
  // minimum opening of the girdle seen along the spine (140 deg; it also stopped a shoulder from
  // following its arm into the hull in test_hull_tracker), a bend limit per spine joint (45 deg)
  // and a limit on the head's direction against the spine (75 deg).
  double max_twist_deg = 60;
  double twist_weight = 1;
  // Hip joints closer than min_hip_ratio of the two hip bones are both pulled apart along their
  // line to that distance, with twist_weight (a pull against the points': they may end a little
  // closer). The hull hardly holds the hips' width (the pelvis's two capsules hinge on LBack
  // inside one mass), and a fit can fold them together: 01_01's first fit at 128^3 folded them
  // to 33 mm, the twist measured against that line passed 90 deg and the arms were swapped
  // (published facing backwards). No body comes near the floor (the shared clips' truths hold
  // 0.49-0.95), so it binds only on a fold.
  double min_hip_ratio = 0.3;
  // Weak prior: every joint is also pulled towards its predicted position.
  double prior_weight = 0.05;
  // A bottom-up extremity agrees with the tracked one within this (statures) and then pulls it.
  double detect_agree_ratio = 0.08;
  double detect_weight = 0.5;
  // Constant-velocity prediction, damped: the pose's change from the frame before includes the
  // fit's corrections, not only motion, and an undamped velocity overshoots every correction and
  // every reversal (measured on 01_01, 07_01, 60_04 and 131_02 at 128^3: 0 and 0.7 each won on
  // two of the four, by 2-7 mm; half is between).
  double velocity_damping = 0.5;
  double max_step_ratio = 0.1;
  // A point is "explained" by the model within this many voxels of a capsule surface (plus the
  // same mm allowance as sigma); scoring. Half a voxel is the hull's quantisation.
  double explained_voxels = 0.5;
  ShakeParams shake{.max_iterations = 12,
                    .sweeps_per_iteration = 3,
                    .target_gain = 1.0,
                    .tolerance_mm = 0.2,
                    .bone_tolerance_mm = 0.01,
                    .max_bone_sweeps = 400};
};

// How well a pose explains the hull: both directions of the silhouette/hull consistency.
struct HullScore {
  double explained = 0;  // fraction of surface points within explained_voxels of the model
  double inside = 0;     // fraction of the bones' axis samples the hull does not rule out
  double value() const { return explained * inside; }
};

struct TrackResult {
  JointPositions joints{};
  std::array<float, kNumJoints> confidence{};
  HullScore score;
  // Each bone's mean surface distance, for the body model (NaN where not measured this frame);
  // its length evidence is HullTracker::length_evidence().
  std::array<double, kNumBones> radius_mm{};
};

// An arm or a leg, from its root (shoulder or hip) out to its tip.
struct Limb {
  std::array<Joint, 5> joints;
  int size;
  Joint root() const { return joints[0]; }
  Joint tip() const { return joints[static_cast<size_t>(size - 1)]; }
};
inline constexpr std::array<Limb, 4> kLimbs = {{
    {{Joint::LSho, Joint::LElb, Joint::LHand, Joint::LFTip}, 4},
    {{Joint::RSho, Joint::RElb, Joint::RHand, Joint::RFTip}, 4},
    {{Joint::LHip, Joint::LKne, Joint::LAnk, Joint::LFoot, Joint::LToe}, 5},
    {{Joint::RHip, Joint::RKne, Joint::RAnk, Joint::RFoot, Joint::RToe}, 5},
}};

class HullTracker {
 public:
  explicit HullTracker(TrackParams params = {});
  // (Re)starts from a pose (acquisition, recovery): the velocity is forgotten.
  void start(const JointPositions& pose);
  void stop() { active_ = false; }
  bool active() const { return active_; }
  // Extremity positions from the bottom-up path, used where they agree (nullptr: none).
  struct Detected {
    const JointPositions* joints = nullptr;
    // Limbs whose predictions are replaced by their detected poses, each hung from its
    // predicted root; they then move with their roots' velocity. Bit i: kLimbs[i] (needs
    // `joints`).
    unsigned limbs = 0;
  };
  // What track() starts from: a second tracker restored to it tracks the same frame another way.
  struct State {
    JointPositions previous, before_previous;
    bool has_velocity = false, active = false;
  };
  State state() const { return {previous_, before_previous_, has_velocity_, active_}; }
  void restore(const State& s);
  // One frame: predict, fit to `surface` (of at most TrackParams::max_points points), score.
  // Keeps the result as the new state.
  const TrackResult& track(const HullSurface& surface, const BodyModel& model, Detected detected);
  // The body model's evidence on the bone lengths at the last tracked pose (result().joints,
  // tracked against `surface` with `model`): Gauss-Newton on the fit's robust residuals. On
  // demand, not in track(): it costs a pass of every surface point over the capsules, ~100
  // multiply-adds per point and a nearest-point search per capsule axis sample the hull rules
  // out, and the model learns from few frames (confident ones, until it is held), while a frame
  // may track several candidates.
  const LengthEvidence& length_evidence(const HullSurface& surface, const BodyModel& model);
  // Scores any pose against the surface with this tracker's capsules (no state change).
  HullScore score(const HullSurface& surface, const BodyModel& model,
                  const JointPositions& pose) const;
  const TrackResult& result() const { return result_; }

 private:
  void fit(const HullSurface& surface, const BodyModel& model, const JointPositions& prior,
           Detected detected);
  void measure(const HullSurface& surface, const BodyModel& model);
  void pull_inside(const HullSurface& surface, const BodyModel& model, const JointPositions& x,
                   size_t stride);
  // Targets that turn the shoulders back within max_twist_deg of the hips (none when within).
  void limit_twist(const JointPositions& x);
  // Targets that pull the hips apart to min_hip_ratio (none when apart).
  void limit_hips(const JointPositions& x, const BodyModel& model);
  // Nearest capsule surface for a point: bone, position along the bone's axis, signed distance.
  struct Hit {
    int bone = 0;
    double t = 0, distance = 0;
  };
  void load_capsules(const BodyModel& model, const JointPositions& pose, double voxel_mm) const;
  static double inside_fraction(const HullSurface& surface, const BodyModel& model,
                                const JointPositions& pose);
  // The hits of points 0, stride, 2 stride, ... against the loaded capsules, in hits_.
  std::span<const Hit> nearest_all(std::span<const Eigen::Vector3f> points, size_t stride) const;
  Eigen::Vector3f axis_point(const Hit& h) const;

  // From measure()'s hits of every surface point.
  void measure_lengths(const HullSurface& surface, const BodyModel& model,
                       std::span<const Hit> hits);

  TrackParams params_;
  Shake shake_;
  bool active_ = false;
  JointPositions previous_{}, before_previous_{};
  bool has_velocity_ = false;
  TrackResult result_;
  LengthEvidence lengths_;
  // Capsules of the current pose, structure of arrays: nearest_all broadcasts one capsule to 16
  // points at a time (points x bones x iterations: the tracker's largest loop).
  struct Capsules {
    alignas(32) std::array<float, kNumBones> ax, ay, az, bx, by, bz, inv_len2, radius;
  };
  mutable Capsules cap_{};
  mutable std::vector<Hit> hits_;  // max_points, for nearest_all
  std::array<double, kNumJoints> support_{};
  std::array<Eigen::Vector3d, kNumJoints> pull_{};
  std::array<int, kNumBones> bone_points_{};
  // Bones from the root (Chest) down to each bone, itself last (-1 ends a chain).
  std::array<std::array<int8_t, kNumBones>, kNumBones> chain_{};
  std::array<double, kNumBones> radial_sum_{};
  std::array<int, kNumBones> radial_n_{};
};

}  // namespace hullpose::pose
