#pragma once
// Fitting the 25-joint / 24-bone model to a labelled pose tree (thesis paper 6).
//
// Shake: the SHAKE constraint algorithm (paper 6, algorithm 1) over the model's bones, plus the
// paper's pseudo-constraints: a joint is tied to a dummy body of infinite mass on a line (an ODR
// fit of tree nodes) or at a point, which pulls it there while the bones keep their lengths.
// ModelFitter: stature from node groups, node groups per bone, lines, the shoulder and hip
// lines from the torso displaced along the two mediolateral axes, rough alignment, then SHAKE
// (algorithm 2 without the frame-to-frame part, which lives in PoseEstimator).
// Both own fixed-size state only: no allocation per frame.
#include <Eigen/Core>
#include <array>
#include <span>
#include <vector>

#include "hullpose/common/joints.hpp"
#include "hullpose/pose/geometry.hpp"
#include "hullpose/pose/pose_tree.hpp"

namespace hullpose::pose {

using JointPositions = std::array<Eigen::Vector3d, kNumJoints>;

// Mean distance between corresponding joints (mm): paper 6's pose-jump measure.
inline double mean_displacement(const JointPositions& a, const JointPositions& b) {
  double sum = 0;
  for (int j = 0; j < kNumJoints; ++j) sum += (a[j] - b[j]).norm();
  return sum / kNumJoints;
}

struct ShakeParams {
  int max_iterations = 60;  // outer iterations (pseudo-constraint step + bone sweeps)
  int sweeps_per_iteration = 3;
  double target_gain = 1.0;    // fraction of the distance to its targets a joint moves per step
  double tolerance_mm = 0.05;  // stop when an iteration moves no joint further than this
  double bone_tolerance_mm = 0.01;  // |length - l| every bone must meet when solve() returns
  // A fit whose bones are still further off than this did not converge (ten times the
  // tolerance: the final sweeps stopped on their count, not on the tolerance).
  double max_bone_error_mm = 0.1;
  int max_bone_sweeps = 400;
  // The last pass, which puts every bone exactly to length after the pseudo-constraints are
  // done, may sweep this many times max_bone_sweeps: nothing pulls against it any more, so it
  // only needs longer when the pose was far from the lengths (a first frame).
  int final_sweep_factor = 4;
};

class Shake {
 public:
  static constexpr int kMaxTargets = 4;
  struct Result {
    int iterations = 0;
    double max_bone_error_mm = 0;
    double mean_target_distance_mm = 0;  // mean joint-to-target distance at the end
  };

  Shake();
  void set_bone_lengths(const std::array<double, kNumBones>& lengths_mm);
  void set_mass(Joint j, double mass);
  void clear_targets();
  void add_line(Joint j, const Line& line, double weight = 1);
  void add_point(Joint j, const Eigen::Vector3d& point, double weight = 1);
  // Distance from the joint to its targets (weighted mean), for confidences.
  double target_distance(Joint j, const Eigen::Vector3d& p) const;
  Result solve(JointPositions& joints, const ShakeParams& params) const;

 private:
  struct Target {
    Line line;
    bool is_point = false;
    double weight = 1;
  };
  // One Gauss-Seidel sweep over the bones; with kMeasure, returns whether every bone was within
  // its bounds before the sweep: (*within)[b] = the squared lengths it must lie strictly between.
  template <bool kMeasure>
  bool sweep_bones(JointPositions& joints, const std::array<Eigen::Vector3d, kNumBones>& reference,
                   const std::array<std::array<double, 2>, kNumBones>* within) const;

  std::array<double, kNumBones> length_{};
  std::array<double, kNumJoints> inv_mass_{};
  std::array<std::array<Target, kMaxTargets>, kNumJoints> target_{};
  std::array<int, kNumJoints> target_count_{};
};

struct FitParams {
  ShakeParams shake;
  // How far the skeleton's ends fall short of the body's ends, in statures. CK3 keeps curve
  // ends, so hands and feet reach their tips; the head, a ball on the neck, thins to a point
  // short of the crown (0.03 measured on synthetic CMU 55_01 at 128^3, by the eval's MPJPE).
  double head_end_ratio = 0.03;
  double hand_end_ratio = 0;
  double foot_end_ratio = 0;
  // Pseudo-constraint weights relative to a limb line: the skeleton's tips are measured, the
  // shoulder and hip lines are the torso displaced by a model offset.
  double tip_weight = 2;
  double tip_mass = 4;
  double torso_offset_weight = 0.5;
  // A node group shorter than this many voxels gives no line (its direction would be noise).
  double min_group_voxels = 2.5;
  // The shoulder plane is fitted to the torso nodes within this many statures of the origin:
  // the upper chest, which turns with the shoulders when the torso twists (paper 6 leaves the
  // extent open; 0.1 has been the value since the first fit, not tuned to a clip).
  double upper_torso_ratio = 0.1;
  // ... together with the arm nodes within this many statures of the origin: the shoulders
  // (the shoulder bone is 0.111 statures in thesis Table 6.7, so 0.15 takes in the shoulder and
  // the top of the upper arm; the value since the shoulder plane was added, not tuned to a clip).
  double shoulder_reach_ratio = 0.15;
};

struct FitResult {
  bool ok = false;
  JointPositions joints{};
  std::array<float, kNumJoints> confidence{};
  int iterations = 0;
  double max_bone_error_mm = 0;
  double mean_target_distance_mm = 0;
};

class ModelFitter {
 public:
  explicit ModelFitter(FitParams params = {});
  // Paper 6: node groups per bone along toe tip -> head top, summed chord lengths (both legs
  // averaged). Needs a valid tree.
  double frame_stature(const LabelledTree& tree) const;
  // Fits the model scaled to `stature_mm` to a valid tree.
  const FitResult& fit(const LabelledTree& tree, double stature_mm);
  const FitResult& result() const { return result_; }
  const Shake& shake() const { return shake_; }

 private:
  // One chain of joints along a tree path, extremity first.
  void fit_chain(const LabelledTree& tree, const std::vector<int32_t>& path,
                 std::span<const Joint> joints, double end_offset_mm, bool point_at_tip);
  double chord_sum(const LabelledTree& tree, const std::vector<int32_t>& path,
                   std::span<const double> groups_mm, double start_mm) const;
  Eigen::Vector3d at_arc(const LabelledTree& tree, const std::vector<int32_t>& path,
                         double arc_mm) const;
  bool group_line(const LabelledTree& tree, const std::vector<int32_t>& path, double from_mm,
                  double to_mm, Line& line) const;
  void compute_arcs(const LabelledTree& tree, const std::vector<int32_t>& path) const;

  FitParams params_;
  Shake shake_;
  FitResult result_;
  double stature_ = 0;
  mutable std::vector<double> arc_;  // arc length per node of the path being processed
};

}  // namespace hullpose::pose
