#pragma once
// Scores pose estimates against a dataset's ground truth (the metrics of thesis chapter 6.4).
// The exact definitions, and how invalid and missing frames count, are in tools/eval/README.md.
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "hullpose/common/dataset.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::eval {

// Summary of a sample set with Tukey's box-and-whisker convention (thesis Fig. 6.4).
// Quantiles interpolate linearly between order statistics (R type 7, numpy's default);
// whiskers end at the most extreme samples within 1.5 IQR of the box; samples beyond are
// outliers. An empty set has count 0 and NaN everywhere.
struct BoxStats {
  size_t count = 0;
  double mean = 0, std = 0;  // std: population standard deviation
  double min = 0, max = 0;
  double q1 = 0, median = 0, q3 = 0;
  double whisker_low = 0, whisker_high = 0;
  std::vector<double> outliers;  // ascending
};
BoxStats box_stats(std::vector<double> samples);

enum class FrameStatus {
  Scored,   // the estimate has the frame and marked it valid: its joints are scored
  Invalid,  // the estimate has the frame but marked it invalid (valid=0)
  Missing,  // the estimate file has no row for this ground-truth frame
};
const char* to_string(FrameStatus status);

struct FrameResult {
  int frame = 0;
  FrameStatus status = FrameStatus::Missing;
  // The true body lies wholly inside the capture volume (always true without a volume). Frames
  // outside are left out of every figure below but the out_of_volume_* counts.
  bool in_volume = true;
  int reason = -1;  // the estimate's reason code; -1 when Missing
  // The rest is NaN / false unless status == Scored.
  double mean_mm = 0;        // mean joint error over the 25 joints
  double extremity_mm = 0;   // mean over head top, hands, feet
  double hands_feet_mm = 0;  // mean over hands and feet (thesis Fig. 6.1)
  Eigen::Vector3d axis_abs_mm = Eigen::Vector3d::Zero();   // mean |est - gt| per axis
  Eigen::Vector3d axis_bias_mm = Eigen::Vector3d::Zero();  // mean (est - gt) per axis
  bool lr_arms_correct = false;
  bool lr_legs_correct = false;
  double stature_gt_mm = 0;   // stature_from_joints(ground truth)
  double stature_est_mm = 0;  // stature_from_joints(estimate)
};

struct EvalResult {
  // Ground-truth frames whose true body lies partly outside the capture volume (when the
  // dataset has a rig): not in `frames` nor in any figure below. They must be flagged invalid
  // or be right: out_of_volume_invalid of them were flagged, the rest were scored with a mean
  // joint error of out_of_volume_mpjpe_mm.
  int out_of_volume_frames = 0;
  int out_of_volume_invalid = 0;
  double out_of_volume_mpjpe_mm = 0;
  int frames = 0;  // in-volume ground-truth frames: the denominator of every *_pct over all frames
  int scored_frames = 0;
  int invalid_frames = 0;
  int missing_frames = 0;
  std::map<int, int> invalid_reasons;  // reason code -> invalid frames with it
  double valid_pct = 0;                // scored_frames / frames

  // Joint errors (Euclidean, mm) pooled over scored frames.
  BoxStats all_joints;   // mean = MPJPE
  BoxStats extremities;  // head top, hands, feet (joints.hpp kExtremities)
  BoxStats hands_feet;   // the thesis' four extremities
  std::array<BoxStats, kNumJoints> per_joint;
  // The per-frame means (FrameResult mean_mm, hands_feet_mm) over scored frames: the
  // statistics of the Fig. 6.1 curves. frame_mean.mean equals all_joints.mean.
  BoxStats frame_mean;
  BoxStats frame_hands_feet;
  int worst_frame = 0;  // the scored frame with the largest mean error (if any)

  // PCK: % of (frame, joint) pairs within the threshold. *_pct counts every ground-truth
  // frame, invalid and missing frames as 25 misses each; *_valid_pct only scored frames.
  double pck50_pct = 0, pck100_pct = 0;
  double pck50_valid_pct = 0, pck100_valid_pct = 0;

  // Over scored frames.
  double lr_correct_pct = 0;  // arms and legs both the right way round
  double lr_arms_correct_pct = 0;
  double lr_legs_correct_pct = 0;
  Eigen::Vector3d axis_abs_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_bias_mm = Eigen::Vector3d::Zero();

  // Stature (see stature_from_joints), means over scored frames.
  double stature_meta_mm = 0;  // meta.json stature_mm: the subject's true stature
  double stature_gt_mm = 0;    // of the ground-truth joints
  double stature_est_mm = 0;   // of the estimated joints
  double stature_est_std_mm = 0;
  double stature_error_mm = 0;       // stature_est_mm - stature_gt_mm
  double stature_error_meta_mm = 0;  // stature_est_mm - stature_meta_mm (thesis Table 6.8)
  // Each bone's length against the truth's, kBones order: the mean over scored frames of
  // (est - gt) / gt, per cent. The stature alone hides a wrong model (a spine too short and a
  // neck too long can add up to the right stature); this says which bones the body model got
  // wrong. NaN without scored frames.
  std::array<double, kNumBones> bone_length_error_pct{};
  double bone_length_error_median_abs_pct = 0;  // the median over the 24 bones of |error|

  std::vector<FrameResult> per_frame;  // one per ground-truth frame, in order
};

// The stature a skeleton's bone lengths imply under the model's bone ratios (joints.hpp
// kBones, thesis Table 6.7): the least-squares S of length_i = ratio_i * S over the 24 bones.
// Pose-independent; exact for a skeleton built from the ratios.
double stature_from_joints(const JointPositions& joints);

// Whether the estimate's left and right limbs of one kind (arms: shoulder, elbow, hand,
// finger tip; legs: hip, knee, ankle, foot, toe) are the right way round: the summed joint
// distances with sides as labelled are no larger than with left and right exchanged.
enum class Limb { Arms, Legs };
bool lr_correct(const JointPositions& estimate, const JointPositions& truth, Limb limb);

// Scores `estimates` against `truth`. Every estimate frame must be a ground-truth frame and
// the estimate must not be empty (else hullpose::Error naming `estimate_name`); both are
// sorted by frame (the readers check it).
// With `volume`, frames whose true body is not wholly inside it (in_capture_volume) are counted
// apart (out_of_volume_*).
EvalResult evaluate(const std::vector<PoseRecord>& truth, const std::vector<PoseRecord>& estimates,
                    const DatasetMeta& meta, const std::string& estimate_name = "estimate",
                    const CaptureVolume* volume = nullptr);

// Whether a true body lies wholly inside the capture volume: every joint at least
// kBodyMarginMm inside its sides and top (the floor is the volume's bottom: feet stand on it).
// The margin is the farthest the body's surface reaches beyond a joint centre (the head's
// radius, ~100 mm).
inline constexpr double kBodyMarginMm = 100;
bool in_capture_volume(const JointPositions& truth, const CaptureVolume& volume);

// Reads DIR/meta.json, DIR/ground_truth.csv and the estimate file, checks they agree, and
// scores them. Throws hullpose::Error naming the file on bad input.
EvalResult evaluate_files(const std::filesystem::path& dataset_dir,
                          const std::filesystem::path& estimate_file);

}  // namespace hullpose::eval
