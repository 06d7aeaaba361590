#include "hullpose/pose/hull_pose_estimator.hpp"

#include <algorithm>
#include <hullpose_msg/skeleton_t.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::pose {
namespace {
using Msg = hullpose_msg::skeleton_t;
}

PoseMode parse_pose_mode(const std::string& value, const char* what) {
  if (value == "bottom-up") return PoseMode::kBottomUp;
  if (value == "track") return PoseMode::kTrack;
  HULLPOSE_THROW(what << ": expected bottom-up or track, got '" << value << "'");
}

HullPoseEstimator::HullPoseEstimator(HullPoseParams params)
    : params_(params),
      bottom_up_(params.bottom_up),
      surface_(params.track.max_points),
      tracker_(params.track),
      candidate_(params.track),
      body_(params.body),
      filter_(params.filter) {}

double HullPoseEstimator::running_score(double s) {
  score_ring_[score_next_] = s;
  score_next_ = (score_next_ + 1) % kScoreWindow;
  score_count_ = std::min(score_count_ + 1, kScoreWindow);
  std::copy_n(score_ring_.begin(), score_count_, score_scratch_.begin());
  const auto mid = score_scratch_.begin() + score_count_ / 2;
  std::nth_element(score_scratch_.begin(), mid, score_scratch_.begin() + score_count_);
  return *mid;
}

// Tracks from the bottom-up pose on a second tracker; takes it over when it explains the hull
// clearly better than the tracked pose.
bool HullPoseEstimator::try_candidate(const JointPositions& detected, double tracked_score) {
  candidate_.start(detected);
  const TrackResult& c = candidate_.track(surface_, body_.model(), {&detected});
  if (c.score.value() <= tracked_score + params_.arbiter.switch_margin) return false;
  tracker_ = candidate_;
  return true;
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
  reacquired_ = false;
  out_ = det;  // reason, detail, timings of the bottom-up path; overwritten below when tracking
  surface_.extract(hull, grid);  // nullptr: no surface
  if (!body_.started()) {
    if (!det.valid) return out_;
    body_.reset(det.stature_mm);
  }
  if (!tracker_.active()) {
    if (!det.valid) {
      out_.fit_us += timer.elapsed_us();
      return out_;
    }
    tracker_.start(det.joints_mm);
    reacquired_ = true;
  }
  const JointPositions* detected = det.valid ? &det.joints_mm : nullptr;
  const TrackResult* r = &tracker_.track(surface_, body_.model(), {detected});
  const bool have_median = score_count_ >= 8;
  ++frames_since_check_;
  if (detected != nullptr && !reacquired_ &&
      (!have_median || r->score.value() < a.check_fraction * median_score_ ||
       frames_since_check_ >= a.check_every)) {
    frames_since_check_ = 0;
    if (try_candidate(*detected, r->score.value())) {
      reacquired_ = true;
      r = &tracker_.result();
    }
  }
  score_ = r->score.value();
  const double floor = have_median ? a.valid_fraction * median_score_ : a.min_score;
  const bool cut_off = surface_.touches_edge();
  const bool good = !surface_.empty() && score_ >= std::max(floor, 0.0) && !cut_off;
  if (good || (reacquired_ && det.valid)) median_score_ = running_score(score_);
  if (good && score_ >= a.model_fraction * median_score_) body_.add(r->length_ratio, r->radius_mm);

  out_.joints_mm = r->joints;
  if (reacquired_) filter_.reset();
  filter_.apply(out_.joints_mm, a.frame_s);
  out_.confidence = r->confidence;
  out_.has_pose = true;
  out_.stature_mm = body_.model().stature_mm();
  out_.valid = good;
  if (good) {
    out_.reason = Msg::REASON_OK;
    out_.detail = "";
  } else if (det.valid || det.reason == Msg::REASON_OK) {
    out_.reason = Msg::REASON_FIT_FAILED;
    out_.detail =
        cut_off ? "hull cut off by the capture volume" : "tracked pose does not explain the hull";
  }
  if (!good) out_.confidence.fill(0);
  out_.fit_us += timer.elapsed_us();
  return out_;
}

}  // namespace hullpose::pose
