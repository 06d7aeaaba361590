#include "hullpose/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <hullpose_msg/skeleton_t.hpp>
#include <limits>
#include <numeric>
#include <optional>

#include "hullpose/common/check.hpp"

namespace hullpose::eval {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

constexpr std::array<Joint, 4> kHandsFeet = {Joint::LHand, Joint::RHand, Joint::LFoot,
                                             Joint::RFoot};
// Left side of each limb; mirror() gives the right.
constexpr std::array<Joint, 4> kLeftArm = {Joint::LSho, Joint::LElb, Joint::LHand, Joint::LFTip};
constexpr std::array<Joint, 5> kLeftLeg = {Joint::LHip, Joint::LKne, Joint::LAnk, Joint::LFoot,
                                           Joint::LToe};

const Eigen::Vector3d& at(const JointPositions& p, Joint j) {
  return p[static_cast<size_t>(index(j))];
}

template <size_t N>
double mean_error(const std::array<double, kNumJoints>& err, const std::array<Joint, N>& joints) {
  double sum = 0;
  for (Joint j : joints) sum += err[static_cast<size_t>(index(j))];
  return sum / static_cast<double>(N);
}

double pct(int part, int whole) {
  return whole > 0 ? 100.0 * part / whole : kNaN;
}

template <typename Range>
double lr_cost(const JointPositions& est, const JointPositions& truth, const Range& left,
               bool swapped) {
  double cost = 0;
  for (Joint l : left) {
    const Joint r = mirror(l);
    cost += (at(est, l) - at(truth, swapped ? r : l)).norm() +
            (at(est, r) - at(truth, swapped ? l : r)).norm();
  }
  return cost;
}

}  // namespace

BoxStats box_stats(std::vector<double> s) {
  BoxStats b;
  b.count = s.size();
  if (s.empty()) {
    b.mean = b.std = b.min = b.max = b.q1 = b.median = b.q3 = b.whisker_low = b.whisker_high = kNaN;
    return b;
  }
  std::sort(s.begin(), s.end());
  const double n = static_cast<double>(s.size());
  b.mean = std::accumulate(s.begin(), s.end(), 0.0) / n;
  double ss = 0;
  for (double x : s) ss += (x - b.mean) * (x - b.mean);
  b.std = std::sqrt(ss / n);
  b.min = s.front();
  b.max = s.back();
  auto quantile = [&](double p) {
    const double h = (n - 1) * p;
    const size_t lo = static_cast<size_t>(std::floor(h));
    if (lo + 1 >= s.size()) return s.back();
    return s[lo] + (h - static_cast<double>(lo)) * (s[lo + 1] - s[lo]);
  };
  b.q1 = quantile(0.25);
  b.median = quantile(0.5);
  b.q3 = quantile(0.75);
  const double iqr = b.q3 - b.q1;
  const double low_fence = b.q1 - 1.5 * iqr, high_fence = b.q3 + 1.5 * iqr;
  b.whisker_low = *std::lower_bound(s.begin(), s.end(), low_fence);
  b.whisker_high = *(std::upper_bound(s.begin(), s.end(), high_fence) - 1);
  for (double x : s)
    if (x < low_fence || x > high_fence) b.outliers.push_back(x);
  return b;
}

const char* to_string(FrameStatus status) {
  switch (status) {
    case FrameStatus::Scored:
      return "scored";
    case FrameStatus::Invalid:
      return "invalid";
    case FrameStatus::Missing:
      return "missing";
  }
  return "?";
}

double stature_from_joints(const JointPositions& joints) {
  double num = 0, den = 0;
  for (const Bone& bone : kBones) {
    num += bone.stature_ratio * (at(joints, bone.child) - at(joints, bone.parent)).norm();
    den += bone.stature_ratio * bone.stature_ratio;
  }
  return num / den;
}

bool lr_correct(const JointPositions& estimate, const JointPositions& truth, Limb limb) {
  if (limb == Limb::Arms)
    return lr_cost(estimate, truth, kLeftArm, false) <= lr_cost(estimate, truth, kLeftArm, true);
  return lr_cost(estimate, truth, kLeftLeg, false) <= lr_cost(estimate, truth, kLeftLeg, true);
}

bool in_capture_volume(const JointPositions& truth, const CaptureVolume& volume) {
  for (const Eigen::Vector3d& p : truth) {
    if (p.x() < volume.min_mm.x() + kBodyMarginMm || p.x() > volume.max_mm.x() - kBodyMarginMm)
      return false;
    if (p.y() < volume.min_mm.y() + kBodyMarginMm || p.y() > volume.max_mm.y() - kBodyMarginMm)
      return false;
    if (p.z() > volume.max_mm.z() - kBodyMarginMm) return false;
  }
  return true;
}

EvalResult evaluate(const std::vector<PoseRecord>& truth, const std::vector<PoseRecord>& estimates,
                    const DatasetMeta& meta, const std::string& estimate_name,
                    const CaptureVolume* volume) {
  HULLPOSE_THROW_UNLESS(!truth.empty(), "the ground truth has no frames");
  HULLPOSE_THROW_UNLESS(!estimates.empty(), estimate_name << ": no frames");
  const int first = truth.front().frame, last = truth.back().frame;

  EvalResult r;
  r.frames = static_cast<int>(truth.size());
  double out_of_volume_sum = 0;
  int out_of_volume_scored = 0;
  r.per_frame.reserve(truth.size());
  std::vector<double> all, extremities, hands_feet, statures_est, statures_gt, frame_means,
      frame_hf;
  std::array<std::vector<double>, kNumJoints> per_joint;
  std::array<double, kNumBones> bone_error_sum{};
  int within50 = 0, within100 = 0, lr_both = 0, lr_arms = 0, lr_legs = 0;
  double worst_mm = -1;

  size_t e = 0;
  for (const PoseRecord& gt : truth) {
    HULLPOSE_THROW_UNLESS(e == estimates.size() || estimates[e].frame >= gt.frame,
                          estimate_name << ": frame " << estimates[e].frame
                                        << " is not a ground-truth frame (the ground truth has "
                                        << r.frames << " frames, " << first << ".." << last << ")");
    FrameResult f;
    f.frame = gt.frame;
    const PoseRecord* est = nullptr;
    if (e < estimates.size() && estimates[e].frame == gt.frame) est = &estimates[e++];
    f.in_volume = volume == nullptr || in_capture_volume(gt.joints, *volume);
    if (!f.in_volume) {
      --r.frames;
      ++r.out_of_volume_frames;
      f.status = est == nullptr ? FrameStatus::Missing
                 : est->valid   ? FrameStatus::Scored
                                : FrameStatus::Invalid;
      f.reason = est == nullptr ? -1 : est->reason;
      f.mean_mm = f.extremity_mm = f.hands_feet_mm = f.stature_gt_mm = f.stature_est_mm = kNaN;
      f.axis_abs_mm.setConstant(kNaN);
      f.axis_bias_mm.setConstant(kNaN);
      if (f.status == FrameStatus::Scored) {
        double sum = 0;
        for (size_t j = 0; j < kNumJoints; ++j) sum += (est->joints[j] - gt.joints[j]).norm();
        out_of_volume_sum += sum / kNumJoints;
        ++out_of_volume_scored;
      } else {
        ++r.out_of_volume_invalid;
      }
      r.per_frame.push_back(f);
      continue;
    }
    if (est == nullptr || !est->valid) {
      f.status = est == nullptr ? FrameStatus::Missing : FrameStatus::Invalid;
      f.reason = est == nullptr ? -1 : est->reason;
      f.mean_mm = f.extremity_mm = f.hands_feet_mm = f.stature_gt_mm = f.stature_est_mm = kNaN;
      f.axis_abs_mm.setConstant(kNaN);
      f.axis_bias_mm.setConstant(kNaN);
      if (est == nullptr) {
        ++r.missing_frames;
      } else {
        ++r.invalid_frames;
        ++r.invalid_reasons[est->reason];
      }
      r.per_frame.push_back(f);
      continue;
    }
    f.status = FrameStatus::Scored;
    f.reason = est->reason;
    ++r.scored_frames;
    std::array<double, kNumJoints> err{};
    for (size_t j = 0; j < kNumJoints; ++j) {
      const Eigen::Vector3d d = est->joints[j] - gt.joints[j];
      err[j] = d.norm();
      f.axis_abs_mm += d.cwiseAbs();
      f.axis_bias_mm += d;
      all.push_back(err[j]);
      per_joint[j].push_back(err[j]);
      within50 += err[j] <= 50.0;
      within100 += err[j] <= 100.0;
    }
    f.axis_abs_mm /= kNumJoints;
    f.axis_bias_mm /= kNumJoints;
    f.mean_mm = std::accumulate(err.begin(), err.end(), 0.0) / kNumJoints;
    f.extremity_mm = mean_error(err, kExtremities);
    f.hands_feet_mm = mean_error(err, kHandsFeet);
    frame_means.push_back(f.mean_mm);
    frame_hf.push_back(f.hands_feet_mm);
    if (f.mean_mm > worst_mm) {
      worst_mm = f.mean_mm;
      r.worst_frame = f.frame;
    }
    for (Joint j : kExtremities) extremities.push_back(err[static_cast<size_t>(index(j))]);
    for (Joint j : kHandsFeet) hands_feet.push_back(err[static_cast<size_t>(index(j))]);
    f.lr_arms_correct = lr_correct(est->joints, gt.joints, Limb::Arms);
    f.lr_legs_correct = lr_correct(est->joints, gt.joints, Limb::Legs);
    lr_arms += f.lr_arms_correct;
    lr_legs += f.lr_legs_correct;
    lr_both += f.lr_arms_correct && f.lr_legs_correct;
    f.stature_gt_mm = stature_from_joints(gt.joints);
    f.stature_est_mm = stature_from_joints(est->joints);
    statures_gt.push_back(f.stature_gt_mm);
    statures_est.push_back(f.stature_est_mm);
    for (size_t b = 0; b < kNumBones; ++b) {
      const double gt_mm =
          (at(gt.joints, kBones[b].child) - at(gt.joints, kBones[b].parent)).norm();
      const double est_mm =
          (at(est->joints, kBones[b].child) - at(est->joints, kBones[b].parent)).norm();
      bone_error_sum[b] += gt_mm > 0 ? (est_mm - gt_mm) / gt_mm : 0;
    }
    r.axis_abs_mm += f.axis_abs_mm;
    r.axis_bias_mm += f.axis_bias_mm;
    r.per_frame.push_back(f);
  }
  HULLPOSE_THROW_UNLESS(e == estimates.size(),
                        estimate_name << ": frame " << estimates[e].frame
                                      << " is not a ground-truth frame (the ground truth has "
                                      << r.frames << " frames, " << first << ".." << last << ")");

  r.out_of_volume_mpjpe_mm =
      out_of_volume_scored > 0 ? out_of_volume_sum / out_of_volume_scored : kNaN;
  const int scored = r.scored_frames;
  r.valid_pct = pct(scored, r.frames);
  r.all_joints = box_stats(std::move(all));
  r.extremities = box_stats(std::move(extremities));
  r.hands_feet = box_stats(std::move(hands_feet));
  for (size_t j = 0; j < kNumJoints; ++j) r.per_joint[j] = box_stats(std::move(per_joint[j]));
  r.frame_mean = box_stats(std::move(frame_means));
  r.frame_hands_feet = box_stats(std::move(frame_hf));
  r.pck50_pct = pct(within50, r.frames * kNumJoints);
  r.pck100_pct = pct(within100, r.frames * kNumJoints);
  r.pck50_valid_pct = pct(within50, scored * kNumJoints);
  r.pck100_valid_pct = pct(within100, scored * kNumJoints);
  r.lr_correct_pct = pct(lr_both, scored);
  r.lr_arms_correct_pct = pct(lr_arms, scored);
  r.lr_legs_correct_pct = pct(lr_legs, scored);
  const double n = scored > 0 ? scored : kNaN;
  r.axis_abs_mm /= n;
  r.axis_bias_mm /= n;
  const BoxStats est_stature = box_stats(std::move(statures_est));
  r.stature_meta_mm = meta.stature_mm > 0 ? meta.stature_mm : kNaN;
  r.stature_gt_mm = box_stats(std::move(statures_gt)).mean;
  r.stature_est_mm = est_stature.mean;
  r.stature_est_std_mm = est_stature.std;
  r.stature_error_mm = r.stature_est_mm - r.stature_gt_mm;
  r.stature_error_meta_mm = r.stature_est_mm - r.stature_meta_mm;
  std::vector<double> bone_abs;
  for (size_t b = 0; b < kNumBones; ++b) {
    r.bone_length_error_pct[b] = 100.0 * bone_error_sum[b] / n;
    if (scored > 0) bone_abs.push_back(std::abs(r.bone_length_error_pct[b]));  // else NaN
  }
  r.bone_length_error_median_abs_pct = box_stats(std::move(bone_abs)).median;
  return r;
}

EvalResult evaluate_files(const std::filesystem::path& dataset_dir,
                          const std::filesystem::path& estimate_file) {
  HULLPOSE_THROW_UNLESS(std::filesystem::is_directory(dataset_dir),
                        dataset_dir.string() << ": not a dataset directory");
  const DatasetPaths paths(dataset_dir);
  const DatasetMeta meta = read_meta(paths.meta());
  const std::vector<PoseRecord> truth = read_ground_truth(paths.ground_truth());
  HULLPOSE_THROW_UNLESS(static_cast<int>(truth.size()) == meta.frames,
                        paths.ground_truth().string()
                            << ": has " << truth.size() << " frames but " << paths.meta().string()
                            << " says " << meta.frames);
  // The capture volume comes from the dataset's rig, when it has one.
  std::optional<CaptureVolume> volume;
  if (std::filesystem::exists(paths.rig())) volume = load_rig(paths.rig()).volume;
  return evaluate(truth, read_estimates(estimate_file), meta, estimate_file.string(),
                  volume ? &*volume : nullptr);
}

}  // namespace hullpose::eval
