#include "hullpose/pose/pose_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <hullpose_msg/skeleton_t.hpp>

#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::pose {

HULLPOSE_LOG_CATEGORY(Pose, "pose")

namespace {
using Msg = hullpose_msg::skeleton_t;
}  // namespace

PoseEstimator::PoseEstimator(PoseParams params)
    : params_(params), builder_(params.tree), fitter_(params.fit) {}

void PoseEstimator::reset() {
  out_ = PoseEstimate{};
  hint_ = TemporalHint{};
  has_accepted_ = has_pending_ = false;
  frames_since_accepted_ = 0;
  stature_.reset();
}

void PoseEstimator::reuse(int8_t reason, const char* detail) {
  out_.valid = false;
  out_.reason = reason;
  out_.detail = detail;
  out_.has_pose = has_accepted_;
  if (has_accepted_) {
    out_.joints_mm = accepted_;
    out_.confidence = accepted_confidence_;
  } else {
    for (auto& p : out_.joints_mm) p.setZero();
    out_.confidence.fill(0);
  }
  hint_.valid = false;  // an invalid labelling is no basis for correspondences (paper 5)
  HULLPOSE_LOG(Pose, Debug) << "frame not fresh: " << detail;
}

bool PoseEstimator::confirms_pending(const JointPositions& pose) const {
  return has_pending_ && mean_displacement(pose, pending_) <= params_.jump_mean_mm;
}

void PoseEstimator::hold_back(const JointPositions& pose, int8_t reason, const char* detail) {
  pending_ = pose;
  has_pending_ = true;
  pending_at_ = frames_since_accepted_;
  reuse(reason, detail);
}

const PoseEstimate& PoseEstimator::estimate(std::span<const Eigen::Vector3i> skeleton,
                                            const VoxelGridSpec& grid) {
  ++frames_since_accepted_;
  out_.frame_stature_mm = 0;
  out_.shake_iterations = 0;
  out_.fit_us = 0;
  out_.has_guess = false;
  StageTimer timer;
  const LabelledTree& tree = builder_.build(skeleton, grid, hint_);
  out_.tree_us = timer.elapsed_us();
  if (skeleton.empty()) {
    reuse(Msg::REASON_EMPTY_HULL, "no skeleton voxels");
    return out_;
  }
  if (!tree.valid) {
    if (params_.fit_low_rank && tree.low_rank) {
      timer.restart();
      // At the running stature once it has settled, else at the tree's own.
      const double stature = stature_.count() >= params_.stature_settle_frames
                                 ? out_.stature_mm
                                 : fitter_.frame_stature(tree);
      if (stature >= params_.min_stature_mm && stature <= params_.max_stature_mm) {
        const FitResult& fit = fitter_.fit(tree, stature);
        out_.has_guess = fit.ok;
        if (fit.ok) out_.guess_mm = fit.joints;
      }
      out_.fit_us = timer.elapsed_us();
    }
    reuse(Msg::REASON_INVALID_TREE, tree.why);
    return out_;
  }
  // Before the first fresh pose, a labelling below acquire_quality is fitted but held back until
  // the next frame's agrees with it (the confirmation a pose jump gets below).
  const bool tentative = !has_accepted_ && tree.quality < params_.acquire_quality;

  timer.restart();
  const double frame_stature = fitter_.frame_stature(tree);
  out_.frame_stature_mm = frame_stature;
  const bool settled = stature_.count() >= params_.stature_settle_frames;
  if (!(frame_stature >= params_.min_stature_mm && frame_stature <= params_.max_stature_mm) ||
      (settled &&
       std::abs(frame_stature - out_.stature_mm) > params_.stature_tolerance * out_.stature_mm)) {
    out_.fit_us = timer.elapsed_us();
    reuse(Msg::REASON_INVALID_TREE, "skeleton size implausible for the subject's stature");
    return out_;
  }
  if (!tentative) out_.stature_mm = stature_.add(frame_stature);
  const FitResult& fit = fitter_.fit(tree, tentative ? frame_stature : out_.stature_mm);
  out_.fit_us = timer.elapsed_us();
  out_.shake_iterations = fit.iterations;
  if (!fit.ok) {
    reuse(Msg::REASON_FIT_FAILED, "model fit did not converge");
    return out_;
  }
  if (tentative) {
    if (pending_at_ != frames_since_accepted_ - 1 || !confirms_pending(fit.joints)) {
      hold_back(fit.joints, Msg::REASON_INVALID_TREE,
                "labelling ranks below the quality needed to acquire a first pose");
      return out_;
    }
    out_.stature_mm = stature_.add(frame_stature);
  }

  // Paper 6, algorithm 2: a pose that jumps further than tau from the last one is not trusted.
  if (has_accepted_ && frames_since_accepted_ <= params_.jump_memory_frames &&
      mean_displacement(fit.joints, accepted_) > params_.jump_mean_mm &&
      !confirms_pending(fit.joints)) {
    hold_back(fit.joints, Msg::REASON_POSE_JUMP, "pose jumped from the previous frame");
    return out_;
  }
  has_pending_ = false;
  has_accepted_ = true;
  frames_since_accepted_ = 0;
  accepted_ = fit.joints;
  accepted_confidence_ = fit.confidence;
  out_.valid = true;
  out_.has_pose = true;
  out_.reason = Msg::REASON_OK;
  out_.detail = "";
  out_.joints_mm = fit.joints;
  out_.confidence = fit.confidence;
  hint_.valid = true;
  for (int s = 0; s < kNumExtremities; ++s)
    hint_.extremity_mm[s] = tree.position[tree.extremity[s]];
  hint_.forward = tree.forward;
  return out_;
}

}  // namespace hullpose::pose
