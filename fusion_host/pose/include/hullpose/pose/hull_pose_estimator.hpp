#pragma once
// The fusion host's pose stage: one frame's hull and curve skeleton in, 25 joints out.
//
// Two ways, chosen by HullPoseParams::mode (`--pose`):
// - bottom-up: the thesis' per-frame path alone (PoseEstimator: tree, labels, SHAKE);
// - track (default): the bottom-up path acquires and re-acquires (a subject it cannot read yet is
//   acquired from the hull until it can, facing where it walks or where its toes point:
//   acquire_from_hull); between, the subject's body model (body_model.hpp, estimated online) is
//   tracked on the hull (hull_tracker.hpp), and every frame the tracked pose is scored against
//   the hull beside the bottom-up one (when valid): the bottom-up pose takes over when it
//   explains the hull clearly better, or when the tracked pose no longer explains it (drift);
//   bottom-up arms and legs take over one at a time when the pose with them explains the hull
//   better (try_limbs). Where the bottom-up path has no valid reading, its low-ranked labelling
//   (a guess) is tested the same way (reading_for).
//   Output optionally through a causal One Euro filter (HullPoseParams::filter, off by default).
//
// Lifecycle: construct once per subject/stream; estimate() per frame; no allocation per frame
// at steady state.
#include <Eigen/Core>
#include <array>
#include <span>

#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/pose/body_model.hpp"
#include "hullpose/pose/foot_facing.hpp"
#include "hullpose/pose/hull_tracker.hpp"
#include "hullpose/pose/one_euro.hpp"
#include "hullpose/pose/pose_estimator.hpp"

namespace hullpose::pose {

enum class PoseMode { kBottomUp, kTrack };
// "bottom-up" or "track"; throws hullpose::Error naming `what` otherwise.
PoseMode parse_pose_mode(const std::string& value, const char* what = "--pose");

struct ArbiterParams {
  // Scores (HullScore::value(), 0..1) are compared relative to the running median of the
  // tracked score, so the thresholds hold whatever the rig's hull quality: a frame is valid
  // when its score reaches valid_fraction of it, and the valid bottom-up pose is tried as a
  // replacement when the tracked score falls below check_fraction of it, or when the two
  // readings disagree (mean joint distance above agree_ratio statures; they differ by ~30 mm on
  // a good frame from the proportions alone): a wrong pose that still scores well (limbs
  // swapped, an arm read along the torso) shows as a disagreement, and where they agree a
  // candidate started from the detection would end where the tracked pose is. This replaced a
  // check every 15 frames: make-eval means of three runs, 128^3 pooled MPJPE 68.2 -> 64.5 mm
  // (64^3 115.8 -> 111.8); checking every frame gave 63.1 at twice the tracking cost, every
  // 5th 65.5, and the periodic check on top of this one changed nothing (64.6).
  double valid_fraction = 0.85;
  double check_fraction = 0.9;
  double agree_ratio = 0.04;
  // The bottom-up candidate replaces the tracked pose when it scores this much higher (a
  // hysteresis: two equally good poses do not alternate).
  double switch_margin = 0.02;
  // Without a median yet (acquisition), a score must reach this absolute floor.
  double min_score = 0.5;
  // Body-model measurements come from frames scoring at least this fraction of the median whose
  // two readings agree (agree_ratio). 0.85 = a valid frame's floor (valid_fraction): the length
  // evidence is robust-weighted and carries its own information, so every frame good enough to
  // publish may add to it (1.0, the median, kept half of them and held the model only after
  // 3.5-7 s on 55_01, 01_01 and 131_02).
  double model_fraction = 0.85;
  double frame_s = 1.0 / 30;  // frame interval for the filter (the rig's rate)
  // Acquisition from the hull alone (HullPoseEstimator::acquire_from_hull) takes a subject whose
  // hull moves faster than this (m/s, over the last kTravelFrames frames) to face where it goes,
  // within 60 deg; slower, to face where its toes point (FootFacing). Walking is 1-1.5 m/s, a
  // standing subject's sway well under 0.1.
  double travel_mps = 0.3;
};

struct HullPoseParams {
  PoseMode mode = PoseMode::kTrack;
  PoseParams bottom_up;
  TrackParams track;
  BodyModelParams body;
  ArbiterParams arbiter;
  FootFacingParams feet;
  OneEuroParams filter;
  // The published head's direction leans on the trunk's with this weight (lean_head_on_trunk;
  // 0: as tracked). Why, in HullPoseEstimator::estimate.
  double head_trunk_weight = 0.5;
};

class HullPoseEstimator {
 public:
  static constexpr int kScoreWindow = 64;

  explicit HullPoseEstimator(HullPoseParams params = {});
  // `hull` is the cleaned hull of the frame (nullptr when fusion failed), `skeleton` its
  // curve-skeleton voxels (empty then), both in `grid`.
  const PoseEstimate& estimate(std::span<const Eigen::Vector3i> skeleton,
                               const fusion::BitGrid* hull, const VoxelGridSpec& grid);
  const PoseEstimate& last() const { return out_; }
  const BodyModel& body_model() const { return body_.model(); }
  const PoseEstimator& bottom_up() const { return bottom_up_; }
  // Tracking-only diagnostics of the last frame.
  bool reacquired() const { return reacquired_; }
  // Whether the bottom-up reading was tracked on the second tracker (the tracked score was low,
  // the two readings disagreed, or the tracker was lost): such a frame costs about twice the
  // tracking.
  bool checked() const { return checked_; }
  double score() const { return score_; }

 private:
  bool try_candidate(const JointPositions& detected, const HullScore& tracked);
  bool try_limbs(const JointPositions& reading, const HullTracker::State& before);
  bool acquire_from_hull(const fusion::BitGrid& hull, const VoxelGridSpec& grid);
  // Where the hull's centroid (x, y) went over the last kTravelFrames frames (mm); false until
  // that many consecutive frames had a hull, or when it moved slower than travel_mps.
  bool travel(Eigen::Vector2d& mm) const;
  // Cosine between the horizontal front of `x` and the hull's travel; 0 without travel.
  double travel_facing(const JointPositions& x) const;
  const JointPositions* reading_for(const PoseEstimate& det, const JointPositions& tracked) const;
  double start_stature(const PoseEstimate& det);
  // The height of the hull's top over an upright pose's head above `stands_on_mm` (z); NaN
  // outside 0.8-1.35 of `stature_mm` (start_stature says why).
  double hull_height(const JointPositions& upright, double stature_mm, double stands_on_mm) const;

  HullPoseParams params_;
  PoseEstimator bottom_up_;
  HullSurface surface_;
  FootFacing feet_;  // acquire_from_hull()'s facing for a subject that does not travel
  HullTracker tracker_, candidate_;
  HullTracker limb_, best_limb_;  // try_limbs()'s: the one being tried, the best so far
  BodyModelEstimator body_;
  OneEuroFilter filter_;
  PoseEstimate out_;
  bool reacquired_ = false, checked_ = false;
  bool from_hull_ = false;  // tracking from acquire_from_hull(), no valid reading since
  JointPositions last_output_{};
  bool has_output_ = false;
  double score_ = 0, median_score_ = 0;
  RunningMedian<kScoreWindow> score_median_;
  // Hull heights over the head in upright settling frames, and at the last hull acquisition
  // (start_stature).
  RunningMedian<16> hull_height_median_;
  double hull_height_ = 0, acquired_height_ = 0;
  // standing_pose()'s height over its stature (Table 6.7's proportions).
  double standing_height_ratio_ = 0;
  // The hull's centroid (x, y) in the last frames (a ring, newest at newest_), and how many of
  // them in a row had a hull (at most the ring's size).
  static constexpr int kTravelFrames = 5;  // 1/6 s at 30 fps
  std::array<Eigen::Vector2d, kTravelFrames + 1> centroid_{};
  size_t newest_ = 0;
  int centroid_frames_ = 0;
};

}  // namespace hullpose::pose
