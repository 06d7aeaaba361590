#pragma once
// Scoring without ground truth (real captures): does the estimated skeleton agree with what the
// cameras saw, and does it behave like a body over time? hullpose-eval uses it automatically
// when the dataset has no ground_truth.csv (tools/eval/README.md).
//  - valid %: estimates marked valid, of the dataset's frames.
//  - silhouette agreement: points sampled along every bone (every sample_step_mm, both ends
//    included) projected into each camera that has a mask for the frame; a point is inside when
//    the mask has foreground within tolerance_px of its pixel. Reported: the share of points
//    inside every present view, per camera, and the share of frames in which every point is
//    inside at least n - 1 of the n present views (one camera may disagree); and per bone, the
//    share of its points inside every present view (which limb leaves the silhouettes).
//  - bone-length coefficient of variation (std / mean over valid frames, per bone): a body's
//    bones do not stretch.
//  - per-joint speed (mean |p(t) - p(t-1)|, mm per frame) and jitter (mean |p(t+1) - 2 p(t) +
//    p(t-1)|, mm per frame², over runs of consecutive valid frames): smooth motion has little
//    jitter; estimates that jump between solutions have a lot.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hullpose/common/dataset.hpp"
#include "hullpose/common/joints.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::eval {

struct ConsistencyOptions {
  double tolerance_px = 2;
  double sample_step_mm = 20;
  int pictures = 4;              // frames drawn in the report, spread over the valid ones ...
  std::vector<int> show_frames;  // ... or these
};

struct CameraAgreement {
  int camera_id = 0;
  size_t points = 0;  // sampled points of frames where this camera has a mask
  double inside_pct = 0;
  int frames = 0;  // frames with a mask
};

struct ConsistencyResult {
  int frames = 0;     // meta.json
  int estimates = 0;  // rows in the estimate file
  int valid = 0;
  double valid_pct = 0;
  int scored_frames = 0;  // valid frames with at least one mask
  size_t points = 0;
  double inside_all_pct = 0;        // points inside every present view
  double frames_n_minus_1_pct = 0;  // frames whose every point is inside >= n-1 present views
  std::vector<CameraAgreement> cameras;
  std::array<double, kNumBones> bone_inside_all_pct{};  // NaN without scored frames
  std::array<double, kNumBones> bone_cv{};              // NaN with fewer than 2 valid frames
  double bone_cv_mean = 0;
  std::array<double, kNumJoints> speed_mm{};
  std::array<double, kNumJoints> jitter_mm{};
  double jitter_mean_mm = 0;
  std::vector<int> frame_inside_pct_frames;  // per scored frame: frame number ...
  std::vector<double> frame_inside_pct;      // ... and its share of points inside every view
  std::vector<int> picture_frames;           // chosen for the report
};

// Points along the bones of one pose (mm), `step_mm` apart at most, joints included, bone by bone
// in kBones order; `bone_of`, if given, gets each point's bone index.
std::vector<Eigen::Vector3d> bone_points(const JointPositions& joints, double step_mm,
                                         std::vector<int>* bone_of = nullptr);

// A bone's key in the reports, unique where kBones' names are not (left and right): its joints'
// names, "LSho-LElb".
std::string bone_key(int bone);

// Reads rig.yaml, meta.json and the masks (cam<ID>/mask_*.png; a missing or unreadable mask is
// that camera absent for that frame). Throws hullpose::Error on an unreadable rig or meta.json.
ConsistencyResult evaluate_consistency(const std::filesystem::path& dataset,
                                       const std::vector<PoseRecord>& estimates,
                                       const ConsistencyOptions& options = {});

}  // namespace hullpose::eval
