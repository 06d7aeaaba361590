#include "hullpose/pose/hull_pose_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <hullpose_msg/skeleton_t.hpp>
#include <limits>
#include <numbers>
#include <utility>

#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::pose {
namespace {
using Msg = hullpose_msg::skeleton_t;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The body's left-to-right direction, horizontal: shoulders and hips together.
Eigen::Vector2d left_to_right(const JointPositions& x) {
  return (x[index(Joint::RSho)] - x[index(Joint::LSho)] + x[index(Joint::RHip)] -
          x[index(Joint::LHip)])
      .head<2>();
}

// Whether two poses have their left and right on the same sides, seen from above.
bool faces_same_way(const JointPositions& a, const JointPositions& b) {
  return left_to_right(a).dot(left_to_right(b)) > 0;
}

// Mean distance (mm) between the trunks of two poses: the joints the limbs hang from (head,
// neck, spine, shoulders, hips).
double trunk_displacement(const JointPositions& a, const JointPositions& b) {
  static constexpr std::array<Joint, 10> kTrunk = {
      Joint::Head,  Joint::Neck, Joint::Chest, Joint::LSho, Joint::RSho,
      Joint::UBack, Joint::Back, Joint::LBack, Joint::LHip, Joint::RHip};
  double sum = 0;
  for (Joint j : kTrunk) sum += (a[index(j)] - b[index(j)]).norm();
  return sum / static_cast<double>(kTrunk.size());
}

PoseParams with_guesses(PoseParams p, bool on) {
  p.fit_low_rank = on;
  return p;
}
}  // namespace

PoseMode parse_pose_mode(const std::string& value, const char* what) {
  if (value == "bottom-up") return PoseMode::kBottomUp;
  if (value == "track") return PoseMode::kTrack;
  HULLPOSE_THROW(what << ": expected bottom-up or track, got '" << value << "'");
}

HullPoseEstimator::HullPoseEstimator(HullPoseParams params)
    : params_(params),
      bottom_up_(with_guesses(params.bottom_up, params.mode == PoseMode::kTrack)),
      surface_(params.track.max_points),
      feet_(params.feet),
      tracker_(params.track),
      candidate_(params.track),
      limb_(params.track),
      best_limb_(params.track),
      body_(params.body),
      filter_(params.filter) {
  constexpr double kStature = 1000;
  standing_height_ratio_ =
      standing_pose(BodyModel::from_stature(kStature), {0, 0}, 0)[index(Joint::HeadTop)].z() /
      kStature;
}

bool HullPoseEstimator::travel(Eigen::Vector2d& mm) const {
  if (centroid_frames_ <= kTravelFrames) return false;
  const size_t n = centroid_.size();
  mm = centroid_[newest_] - centroid_[(newest_ + n - kTravelFrames) % n];
  return mm.norm() > params_.arbiter.travel_mps * 1000 * kTravelFrames * params_.arbiter.frame_s;
}

double HullPoseEstimator::travel_facing(const JointPositions& x) const {
  Eigen::Vector2d moved;
  const Eigen::Vector2d l2r = left_to_right(x);
  if (!travel(moved) || l2r.squaredNorm() < 1e-12) return 0;
  const Eigen::Vector2d front(-l2r.y(), l2r.x());  // z up: the front is left-to-right turned left
  return front.dot(moved) / (front.norm() * moved.norm());
}

// Which reading the tracked pose is tested against (try_candidate, try_limbs): the valid one,
// or else the bottom-up path's guess (PoseEstimate::guess_mm: a labelling that ranks too low to
// be valid, which the hull may still prefer: a labelling ranks low where its limb branches are
// far from their expected lengths, short or merged, where the tracker needs help most). A guess has
// no say in which way the body faces (its left and right are the least certain part of it): one
// that turns the tracked pose round is only tested where the tracked pose faces against the hull's
// travel and the guess along it (a walking subject faces where it goes, as in acquire_from_hull).
// Without this rule such guesses turned the salsa clip 60_01 backwards for about 40 frames; with
// it, 131_01's re-entry (at 128^3 tracked backwards for eight frames, 300 mm off) is turned round
// on its third frame.
const JointPositions* HullPoseEstimator::reading_for(const PoseEstimate& det,
                                                     const JointPositions& tracked) const {
  if (det.valid) return &det.joints_mm;
  if (!det.has_guess) return nullptr;
  constexpr double kAgainst = -0.5;  // front more than 120 deg from the travel
  if (faces_same_way(det.guess_mm, tracked) ||
      (travel_facing(tracked) < kAgainst && travel_facing(det.guess_mm) > 0))
    return &det.guess_mm;
  return nullptr;
}

// Acquisition from the hull alone, for a subject the tree cannot read yet (arms held against the
// body give the curve skeleton no arm branches; a subject walking in at the volume's edge). The
// hull of an upright body is nearly the same seen from the front and from the back, so the fit
// alone cannot say which way the subject faces (tried on the shared clips: facing chosen by the
// better fit of all eight, the salsa clip 60_01 at 64^3 was read backwards, left for right, for
// 69 frames). Two cues can: a subject walking faces where it goes (a hull that travels,
// travel_mps), and one that stands has its toes in front of its legs (FootFacing). The model
// standing upright (standing_pose(), its stature from the hull's height) over the hull's
// centroid is tracked from facings about that heading and three arm poses, and the best is kept
// when it explains the hull as an acquisition must (min_score).
bool HullPoseEstimator::acquire_from_hull(const fusion::BitGrid& hull, const VoxelGridSpec& grid) {
  const auto points = surface_.points();
  if (points.empty() || surface_.touches_edge()) return false;
  // The subject stands on the hull's bottom (the floor, or a step) where the hull shows its feet;
  // a hull without them (carved away, out of some view) stands on the floor.
  double top = 0, bottom = std::numeric_limits<double>::max();
  for (const Eigen::Vector3f& p : points) {
    top = std::max(top, static_cast<double>(p.z()));
    bottom = std::min(bottom, static_cast<double>(p.z()));
  }
  top += 0.5 * surface_.voxel_mm();  // voxel centres to the faces
  bottom -= 0.5 * surface_.voxel_mm();
  Eigen::Vector2d toes, toward;  // where its toes point; where it goes, or else the toes' way
  const bool feet = feet_.measure(hull, grid, (top - bottom) / standing_height_ratio_, toes);
  if (!feet) bottom = 0;
  if (!travel(toward)) {
    if (!feet) return false;
    toward = toes;
  }
  if (!body_.started()) body_.reset((top - bottom) / standing_height_ratio_);
  const double heading = std::atan2(toward.y(), toward.x());
  constexpr double kDeg = std::numbers::pi / 180;
  // Arms hanging, half raised, or spread in a T (where takes start): the fit turns a limb only
  // so far from where it starts, and arms started hanging stay down beside spread ones. Raised
  // arms replace lower ones only where they explain the hull clearly better (switch_margin): on
  // a subject whose arms hang both explain it alike, and the half-raised start tracked worse.
  double best = -1, best_arms = 0;
  for (double arms : {kHangingArmRad, std::numbers::pi / 4, std::numbers::pi / 2})
    for (double turn : {-60.0, -30.0, 0.0, 30.0, 60.0}) {  // a side step; turned-out feet
      candidate_.start(
          standing_pose(body_.model(), centroid_[newest_], heading + turn * kDeg, bottom, arms));
      const double score = candidate_.track(surface_, body_.model(), {}).score.value();
      const double margin = arms != best_arms ? params_.arbiter.switch_margin : 0;
      if (best < 0 || score > best + margin) {
        best = score;
        best_arms = arms;
        tracker_ = candidate_;
      }
    }
  if (best < params_.arbiter.min_score) {
    tracker_.stop();
    return false;
  }
  // The acquired pose stands upright by construction: the hull over its head, above what it
  // stands on, bounds the stature from below for the readings to come (start_stature).
  const double h = hull_height(tracker_.result().joints, body_.model().stature_mm(), bottom);
  if (std::isfinite(h)) acquired_height_ = h;
  return true;
}

// Tracks from the bottom-up pose on a second tracker; takes it over when it explains the hull
// clearly better than the tracked pose. Where the two trunks agree (trunk_displacement within
// agree_ratio), the readings differ in their limbs only, and the switch is judged as try_limbs()
// judges a limb: neither part of the score may fall. On the product alone, a reading that folds
// an arm into the torso replaced a tracked arm that was right (01_01 frame 152 at 128^3: the
// folded arm put more of the bones inside the hull, 0.78 -> 0.92 of the samples, and explained
// less of it, 0.92 -> 0.90; the elbow then stayed 400-440 mm off for eight frames). A reading
// whose trunk is elsewhere (a pose tracked backwards, a re-entry) is still taken on the product
// alone: with the explained part held on every switch, 131_01's re-entry at 128^3 stayed ~300 mm
// off for five frames (docs/perf-log.md, session 21).
bool HullPoseEstimator::try_candidate(const JointPositions& detected, const HullScore& tracked) {
  candidate_.start(detected);
  const TrackResult& c = candidate_.track(surface_, body_.model(), {&detected});
  if (c.score.value() <= tracked.value() + params_.arbiter.switch_margin) return false;
  const bool limbs_only = trunk_displacement(detected, tracker_.result().joints) <=
                          params_.arbiter.agree_ratio * body_.model().stature_mm();
  if (limbs_only && (c.score.explained < tracked.explained || c.score.inside < tracked.inside))
    return false;
  tracker_ = candidate_;
  return true;
}

// The whole-body check (try_candidate) misses a single limb gone wrong: an arm the tracker left
// in a wrong place the hull does not rule out (inside the torso, where no surface of its own
// pulls it out) while the curve skeleton shows its branch elsewhere moves the mean joint
// distance by a few per cent of the stature only. Where a limb's bottom-up tip lies beyond the
// distance at which it would pull the tracked tip (TrackParams::detect_agree_ratio), the frame
// is tracked again from the state before it with that limb started at its reading, hung from
// the predicted root. The one that explains most of the hull replaces the tracked pose if it
// explains more than the tracked pose does; then the other limbs are tried again on top of it,
// as more than one can be wrong at once (both arms, on the salsa clips). The inside part of the
// score does not judge here: it rewards a limb hidden in the trunk, where nothing rules it out,
// over one that found its own surface but lies partly outside a thin, coarsely carved hand or
// forearm. 131_02's right forearm stayed buried in the trunk for frames 150-261 at 128^3 while
// the reading's arm, tracked, came within 8-17 mm at the finger tip (340 mm for the buried one)
// and explained more, but put 4-7 more of the 120 axis samples outside the hull. Judged against
// the ground truth over every limb tried on the shared clips (docs/perf-log.md, session 25), the
// explained part alone picks the nearer limb more often than both parts together, at 64^3 and
// 128^3; a reading's limb that the hull does not show explains less and is still not taken
// (test_pose_recovery). The rest
// of the body and its velocity are kept, which a restart from the whole bottom-up pose would
// lose. A reading that faces the other way has its left and right the other way round too: none
// of its limbs is tried. At most 4 + 3 + 2 + 1 trackings, in frames where limbs disagree.
bool HullPoseEstimator::try_limbs(const JointPositions& reading, const HullTracker::State& before) {
  if (!faces_same_way(reading, tracker_.result().joints)) return false;
  const double far = params_.track.detect_agree_ratio * body_.model().stature_mm();
  unsigned taken = 0;
  for (;;) {
    const TrackResult& now = tracker_.result();
    double best = now.score.explained;
    unsigned pick = 0;
    for (size_t i = 0; i < kLimbs.size(); ++i) {
      const unsigned bit = 1u << i;
      const int tip = index(kLimbs[i].tip());
      if ((taken & bit) != 0 || (reading[tip] - now.joints[tip]).norm() <= far) continue;
      limb_.restore(before);
      const HullScore& c = limb_.track(surface_, body_.model(), {&reading, taken | bit}).score;
      if (c.explained <= best) continue;
      best = c.explained;
      pick = bit;
      std::swap(limb_, best_limb_);
    }
    if (pick == 0) return taken != 0;
    taken |= pick;
    std::swap(tracker_, best_limb_);
  }
}

// The body model's starting stature. The bottom-up reading's can be far off (21 % short on the
// salsa clips: arms folded into the torso shorten every path of the curve skeleton), and the
// model cannot grow out of a start that small: the hull above its head lies beyond the tracker's
// gate. A lower bound that no reading can shorten: the stature is the toe-to-head-top path along
// the bones (anthropometry.hpp), so it is at least the head top's height above the floor (z = 0,
// docs/conventions.md), and for an upright subject (nothing but the head near the top) the
// hull's top over the head is that height to a voxel. The start is the larger of the reading
// and the median of those heights over the settling frames. Heights outside 0.8-1.35 of the
// reading are taken for something else (a hand above the head, a cut-off hull): standing height
// is 0.88-0.96 of the path on the CMU subjects, and 60_01's reading, 25 % short, gives 1.30.
// The last hull acquisition's height (above what it stood the model on: acquire_from_hull)
// bounds it too, so a reading shorter still, or not upright, cannot restart the model below
// it. It is not one of the median's heights: an acquisition stands the model on the hull's
// bottom, which lies above the floor where thin feet are carved away (08_02 at 128^3: 77 mm),
// and that one low height lowered the median by a rank (stature error -6.0 -> -8.8 %). The salsa
// clips replayed without their first (T-pose) frame are acquired from the hull, and their first
// valid readings, 25 % short and not upright, restarted the model there; it never explained the
// hull again (60_01: 4.7 % of the frames valid; docs/perf-log.md, session 26).
double HullPoseEstimator::start_stature(const PoseEstimate& det) {
  const JointPositions& j = det.joints_mm;
  const double head_top = j[index(Joint::HeadTop)].z(), clearance = 0.05 * det.stature_mm;
  bool upright = true;
  for (int k = 0; k < kNumJoints; ++k) {
    const Joint joint = static_cast<Joint>(k);
    if (joint != Joint::HeadTop && joint != Joint::Head && joint != Joint::Neck &&
        j[k].z() > head_top - clearance)
      upright = false;
  }
  if (const double h = upright ? hull_height(j, det.stature_mm, 0) : kNaN; std::isfinite(h))
    hull_height_ = hull_height_median_.add(h);
  return std::max({det.stature_mm, hull_height_, acquired_height_});
}

double HullPoseEstimator::hull_height(const JointPositions& upright, double stature_mm,
                                      double stands_on_mm) const {
  const double h = surface_.top_mm(upright[index(Joint::HeadTop)].head<2>(), 0.08 * stature_mm) -
                   surface_.voxel_mm() - stands_on_mm;
  return h > 0.8 * stature_mm && h < 1.35 * stature_mm ? h : kNaN;
}

const PoseEstimate& HullPoseEstimator::estimate(std::span<const Eigen::Vector3i> skeleton,
                                                const fusion::BitGrid* hull,
                                                const VoxelGridSpec& grid) {
  const PoseEstimate& det = bottom_up_.estimate(skeleton, grid);
  if (params_.mode == PoseMode::kBottomUp) {
    out_ = det;
    return out_;
  }
  StageTimer timer;
  const ArbiterParams& a = params_.arbiter;
  reacquired_ = checked_ = false;
  out_ = det;  // reason, detail, timings of the bottom-up path; overwritten below when tracking
  surface_.extract(hull, grid);  // nullptr: no surface
  if (surface_.empty()) {
    centroid_frames_ = 0;
  } else {
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const Eigen::Vector3f& p : surface_.points()) c += p.head<2>().cast<double>();
    newest_ = (newest_ + 1) % centroid_.size();
    centroid_[newest_] = c / static_cast<double>(surface_.points().size());
    centroid_frames_ = std::min(centroid_frames_ + 1, kTravelFrames + 1);
  }
  // The body model starts at start_stature() (the bottom-up path's running stature, or the
  // hull's height if larger), restarting on each valid frame until that median has settled (one
  // frame's stature can be far off).
  const bool settling = bottom_up_.stature_frames() <= params_.bottom_up.stature_settle_frames;
  if (det.valid && (!body_.started() || settling)) body_.reset(start_stature(det));
  // A pose acquired from the hull alone bridges the frames until the tree reads the subject; the
  // first valid reading takes over, as if it were the first acquisition.
  if (!tracker_.active() || (from_hull_ && det.valid)) {
    from_hull_ = false;
    if (det.valid) {
      tracker_.start(det.joints_mm);
    } else if (hull != nullptr && acquire_from_hull(*hull, grid)) {
      from_hull_ = true;
    } else {
      out_.fit_us += timer.elapsed_us();
      return out_;
    }
    reacquired_ = true;
  }
  body_.tick();
  const JointPositions* detected = det.valid ? &det.joints_mm : nullptr;
  const HullTracker::State before = tracker_.state();
  const TrackResult* r = &tracker_.track(surface_, body_.model(), {detected});
  const bool have_median = score_median_.count() >= 8;
  // A disagreement is checked: the tracked pose may be the wrong one (ArbiterParams).
  const double agree_mm = a.agree_ratio * body_.model().stature_mm();
  const JointPositions* reading = reading_for(det, r->joints);
  if (reading != nullptr && !reacquired_ &&
      (!have_median || r->score.value() < a.check_fraction * median_score_ ||
       mean_displacement(*reading, r->joints) > agree_mm)) {
    checked_ = true;
    if (try_candidate(*reading, r->score)) {
      reacquired_ = true;
      r = &tracker_.result();
    }
  }
  if (reading != nullptr && !reacquired_ && try_limbs(*reading, before)) r = &tracker_.result();
  score_ = r->score.value();
  const double floor = have_median ? a.valid_fraction * median_score_ : a.min_score;
  const bool cut_off = surface_.touches_edge();
  const bool tracked_ok = !surface_.empty() && score_ >= std::max(floor, 0.0) && !cut_off;
  // When the tracked pose no longer explains the hull and a valid detection exists, the tracker
  // was lost: it restarts from the detection, refined on the hull.
  if (!tracked_ok && detected != nullptr && !reacquired_) {
    if (!checked_) {
      candidate_.start(*detected);
      candidate_.track(surface_, body_.model(), {detected});
      checked_ = true;
    }
    tracker_ = candidate_;
    r = &tracker_.result();
    reacquired_ = true;
    score_ = r->score.value();
  }
  // Whichever path the pose came from, it is published only if it explains the hull as well as
  // the frames before it usually did. A valid bottom-up reading that, refined on the hull, still
  // does not is wrong: on the shared clips at 128^3 all six such frames were 71-297 mm off
  // (131_01's kneeling subject with its legs read forward). Until that usual level is known (the
  // running median) the reading stands: a sparse rig's hull, mostly ghost volume, explains too
  // little of any pose for an absolute floor (held to min_score, the package test's rig of 4
  // cameras at 64^3 published nothing). A valid reading also vouches for a hull that the capture
  // volume cuts off, which tracking alone does not publish.
  const bool explains = !have_median || (!surface_.empty() && score_ >= floor);
  const bool good = tracked_ok || (det.valid && explains);
  // A hull-acquired pose that stops explaining the hull is searched for afresh next frame.
  if (from_hull_ && !tracked_ok) tracker_.stop();
  // The score's typical level follows the motion (a cartwheel explains its hull less well than
  // standing): every published frame counts.
  if (good && !from_hull_) median_score_ = score_median_.add(score_);
  // The body model learns from confident frames only: the tracked pose explains the hull as well
  // as usual and the independent bottom-up reading agrees with it.
  const bool agree = detected != nullptr && mean_displacement(*detected, r->joints) <= agree_mm;
  if (tracked_ok && agree && score_ >= a.model_fraction * median_score_) {
    static const LengthEvidence kHeld;  // a held model takes no length evidence
    body_.add(body_.held() ? kHeld : tracker_.length_evidence(surface_, body_.model()),
              r->radius_mm);
  }

  // A re-acquisition that moves the pose as far as paper 6's jump threshold starts the filter
  // afresh (smoothing across it would drag the old pose along); a smaller one is smoothed.
  const bool jumped =
      has_output_ && mean_displacement(r->joints, last_output_) > params_.bottom_up.jump_mean_mm;
  out_.joints_mm = r->joints;
  // The head's capsule is nearly a ball, so the hull hardly shows the head's direction: the
  // tracked crown (HeadTop) was 40-75 mm off on the CMU clips at 128^3 with the Head joint
  // 18-40 mm off. The trunk's axis, which the hull shows well, is a prior for it (a head stays
  // near it in most postures). Published only: leaned inside the tracker, the lean compounded
  // frame over frame onto the trunk's axis and lost where the head bends on its own (131_02,
  // a subject bent over: 45 -> 77 mm), and moved arbitration elsewhere (01_01's right arm).
  lean_head_on_trunk(out_.joints_mm, params_.head_trunk_weight);
  if (jumped) filter_.reset();
  filter_.apply(out_.joints_mm, a.frame_s);
  // The filter (when on, --smooth-hz) smooths every joint on its own, which changes bone lengths
  // by up to ~1 %, and SHAKE meets them only to its tolerance: the published pose keeps its
  // directions and gets the model's lengths back, so every frame of a held model has exactly
  // its lengths.
  impose_bone_lengths(out_.joints_mm, body_.model().length_mm);
  out_.model_version = body_.version();
  last_output_ = out_.joints_mm;
  has_output_ = true;
  out_.confidence = r->confidence;
  out_.has_pose = true;
  out_.stature_mm = body_.model().stature_mm();
  out_.valid = good;
  if (good) {
    out_.reason = Msg::REASON_OK;
    out_.detail = "";
  } else if (det.valid || det.reason == Msg::REASON_OK) {
    out_.reason = Msg::REASON_FIT_FAILED;
    out_.detail = cut_off     ? "hull cut off by the capture volume"
                  : det.valid ? "bottom-up reading does not explain the hull"
                              : "tracked pose does not explain the hull";
  }
  if (!good) out_.confidence.fill(0);
  out_.fit_us += timer.elapsed_us();
  return out_;
}

}  // namespace hullpose::pose
