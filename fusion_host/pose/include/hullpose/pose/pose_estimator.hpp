#pragma once
// The pose stage of the fusion host: curve-skeleton voxels of one frame in, 25 joints out.
// Owns the tree builder and the model fitter, and the little the method keeps between frames:
// the previous valid labelling (temporal correspondence of the extremities), the last fresh
// pose (reused, flagged, when the tree is invalid or the pose jumps), and a running median of
// the stature. Construct once per subject/stream; estimate() per frame; no allocation per
// frame at steady state.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>

#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/pose/model_fit.hpp"
#include "hullpose/pose/pose_tree.hpp"
#include "hullpose/pose/running_median.hpp"

namespace hullpose::pose {

struct PoseParams {
  TreeParams tree;
  FitParams fit;
  // tau of paper 6: a fresh pose whose mean joint displacement from the last accepted pose
  // exceeds this is a jump. A jump is accepted when the next frame agrees with it (the motion
  // was real), and the check is skipped after `jump_memory_frames` frames without a fresh pose.
  double jump_mean_mm = 150;
  // Until the first fresh pose there is no previous pose to catch a wrong labelling: the tree's
  // quality must reach this stricter level, or the minimum (TreeParams::min_quality, which holds
  // afterwards) on two consecutive frames whose fitted poses agree within jump_mean_mm.
  double acquire_quality = 0.6;
  int jump_memory_frames = 5;
  // Stature: running median over the valid frames; a frame whose own estimate is off the
  // median by more than `stature_tolerance` (once `stature_settle_frames` frames are in) or
  // outside the absolute bounds has a broken skeleton and counts as an invalid tree.
  double stature_tolerance = 0.2;
  int stature_settle_frames = 10;
  double min_stature_mm = 800, max_stature_mm = 2500;
  // Fit a low-ranked labelling (LabelledTree::low_rank) too, as PoseEstimate::guess_mm (at the
  // running stature, or the tree's own until it has settled). The frame stays invalid; the tracking
  // stage tests the guess against the hull (HullPoseEstimator). Off for the bottom-up path alone:
  // nothing would use it.
  bool fit_low_rank = false;
};

struct PoseEstimate {
  bool valid = false;                          // a fresh estimate of this frame
  int8_t reason = 0;                           // hullpose_msg::skeleton_t::REASON_*
  const char* detail = "";                     // static text behind the reason
  JointPositions joints_mm{};                  // common/joints.hpp order; the reused pose if !valid
  std::array<float, kNumJoints> confidence{};  // 0 when no pose exists at all
  bool has_pose = false;                       // false until the first fresh pose
  double stature_mm = 0;                       // running estimate
  // skeleton_t::model_version: 0 = provisional (bone lengths may change from frame to frame),
  // n >= 1 = the joints have exactly the n-th held body model's bone lengths.
  int32_t model_version = 0;
  double frame_stature_mm = 0;  // this frame's own estimate (0 without a valid tree)
  int shake_iterations = 0;
  int64_t tree_us = 0, fit_us = 0;  // stage timings
  // This frame's low-ranked labelling, fitted (PoseParams::fit_low_rank); only when !valid.
  bool has_guess = false;
  JointPositions guess_mm{};
};

class PoseEstimator {
 public:
  static constexpr int kStatureWindow = 64;

  explicit PoseEstimator(PoseParams params = {});
  const PoseEstimate& estimate(std::span<const Eigen::Vector3i> skeleton,
                               const VoxelGridSpec& grid);
  const PoseEstimate& last() const { return out_; }
  const LabelledTree& tree() const { return builder_.tree(); }
  // Valid frames in the running stature (it is settled from params.stature_settle_frames on).
  int stature_frames() const { return stature_.count(); }
  void reset();

 private:
  void reuse(int8_t reason, const char* detail);
  // A pose nobody vouches for yet (a jump, or a first labelling below acquire_quality): kept as
  // pending_ and the frame reported not fresh; a later pose within jump_mean_mm confirms it.
  void hold_back(const JointPositions& pose, int8_t reason, const char* detail);
  bool confirms_pending(const JointPositions& pose) const;

  PoseParams params_;
  PoseTreeBuilder builder_;
  ModelFitter fitter_;
  PoseEstimate out_;
  TemporalHint hint_;
  JointPositions accepted_{};  // last fresh pose
  std::array<float, kNumJoints> accepted_confidence_{};
  // A rejected jump, or before the first fresh pose a labelling below acquire_quality, kept to
  // confirm against the next frame (pending_at_: frames_since_accepted_ when kept).
  JointPositions pending_{};
  bool has_accepted_ = false, has_pending_ = false;
  int frames_since_accepted_ = 0, pending_at_ = 0;
  RunningMedian<kStatureWindow> stature_;
};

}  // namespace hullpose::pose
