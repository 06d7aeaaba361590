#pragma once
// Intrinsic calibration of one camera from checkerboard views (Zhang's method through
// cv::calibrateCamera), with the live feedback of Calvin (thesis paper 1): as each view arrives,
// how much of the image the boards cover, how many views are kept and the view's reprojection
// error; views whose error stands out are rejected before the final estimate.
#include <Eigen/Geometry>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hullpose/calibrate/board.hpp"
#include "hullpose/common/camera.hpp"

namespace hullpose::calibrate {

struct IntrinsicsOptions {
  int min_views = 8;                // kept views needed for an estimate
  double outlier_factor = 3.0;      // reject a view whose RMS exceeds factor x median ...
  double outlier_floor_px = 1.0;    // ... and this absolute floor
  double min_tilt_spread_deg = 10;  // views must differ this much in board orientation
  bool estimate_k3 = true;
  // Re-estimate as views arrive, for the per-view error in the feedback (costs a calibration
  // each time the views grow by half; off when nobody reads the feedback).
  bool live_estimates = true;
};

// What the user sees after each view (printed as views are captured).
struct ViewFeedback {
  int camera_id = 0;
  std::string view;
  bool found = false;
  int views_kept = 0;
  double coverage = 0;                // fraction of the image covered by boards so far
  std::optional<double> view_rms_px;  // once a first estimate exists
  bool outlier = false;               // the view would be rejected by the current estimate
};

struct BoardView {
  std::string view;
  std::vector<cv::Point2f> corners;
};

struct IntrinsicsResult {
  CameraModel camera;  // intrinsics, image size and id; R = I, t = 0
  double rms_px = 0;   // over kept views
  double coverage = 0;
  std::vector<BoardView> kept;
  std::vector<std::string> rejected;
  std::vector<Eigen::Isometry3d> cam_from_board;  // per kept view
  std::vector<double> view_rms_px;                // per kept view
};

class IntrinsicsCalibrator {
 public:
  IntrinsicsCalibrator(int camera_id, BoardSpec board, IntrinsicsOptions options);

  // `corners` empty = no board found in this view. Every image of a camera must have one size.
  ViewFeedback add_view(const std::string& view, cv::Size image_size,
                        std::vector<cv::Point2f> corners);
  int views_found() const { return static_cast<int>(views_.size()); }
  int views_seen() const { return seen_; }
  // Throws hullpose::Error naming the camera: no board found, too few views, degenerate views.
  IntrinsicsResult calibrate() const;
  // With the intrinsics known (another tool's calibration): only each view's board pose, by
  // solvePnP. Needs one view; throws hullpose::Error naming the camera if none, or if the image
  // size is not `known`'s.
  IntrinsicsResult with_known(const CameraModel& known) const;

 private:
  struct Estimate {
    cv::Mat K, dist;
    std::array<double, 4> sigma{};         // one-sigma fx, fy, cx, cy
    std::vector<Eigen::Vector3d> normals;  // board normals per view, camera frame
  };
  // Throws if the views were degenerate (all parallel) or leave the intrinsics uncertain.
  void check_determined(const Estimate& e, size_t views) const;
  Estimate run_opencv(const std::vector<const BoardView*>& views, std::vector<cv::Mat>& rvecs,
                      std::vector<cv::Mat>& tvecs, std::vector<double>& per_view,
                      double& rms) const;

  int camera_id_;
  BoardSpec board_;
  IntrinsicsOptions options_;
  cv::Size image_size_;
  int seen_ = 0;
  std::vector<BoardView> views_;
  cv::Mat coverage_;  // coarse grid over the image, 255 where a board has been
  std::optional<Estimate> live_;
  size_t live_views_ = 0;  // views the live estimate was made from
  std::vector<double> live_errors_;
};

// Per-view RMS reprojection error (px) of `corners` for a board at `cam_from_board`.
double view_rms_px(const CameraModel& camera, const Eigen::Isometry3d& cam_from_board,
                   const BoardSpec& board, const std::vector<cv::Point2f>& corners);

}  // namespace hullpose::calibrate
