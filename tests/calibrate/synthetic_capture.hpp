#pragma once
// Synthetic calibration captures for the tests: a rig like the thesis lab (7 cameras in a ring,
// one on the ceiling, 800x600, realistic distortion), a capture plan (close-ups per camera,
// boards spread over the volume seen by several cameras, the board on the floor) and a renderer
// that draws the board through the exact camera model (anti-aliased by 4x4 supersampling) with
// every inner corner displaced by seeded Gaussian noise, so detected corners carry a known noise
// level. Pixel centres sit at integer coordinates, as in OpenCV.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "hullpose/calibrate/board.hpp"
#include "hullpose/calibrate/view_provider.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::calibrate::testing {

Rig make_ring_rig(unsigned seed);

struct PlannedView {
  std::string name;
  Eigen::Isometry3d world_from_board;
};

// The capture tools/calibrate/README.md recommends, by default.
struct CapturePlan {
  int close_ups = 12;  // per camera
  int shared = 16;     // boards in the middle of the volume
  int floors = 5;      // "floor" at the origin, then "floor2", "floor3", ... around it
  double min_tilt_deg = 40, max_tilt_deg = 60;  // close-ups, from facing their camera
};

// The views of `plan`; names sort in plan order.
std::vector<PlannedView> make_capture_plan(const Rig& rig, const BoardSpec& board,
                                           const CapturePlan& plan, unsigned seed);
// The floor view names make_capture_plan gives, the first at the origin.
std::vector<std::string> floor_view_names(const CapturePlan& plan);

// The board on the floor, printed face up, its corner-grid centre at the world origin.
Eigen::Isometry3d floor_board_pose(const BoardSpec& board);

// The corners camera `c` would detect of a board at `world_from_board`, with Gaussian noise of
// `noise_px` per axis; empty if the printed face is not seen head-on enough (within 66 degrees,
// about the detector's reach) or the board is not wholly inside the image. The corner-level
// stand-in for render + detect.
std::vector<cv::Point2f> project_board(const CameraModel& c, const BoardSpec& board,
                                       const Eigen::Isometry3d& world_from_board, double noise_px,
                                       std::mt19937& rng);

// One camera's image of one instant, as the calibrator gets it.
struct Detection {
  std::string view;
  int camera = 0;
  cv::Size size;
  std::vector<cv::Point2f> corners;  // empty: no board found
};

class BoardRenderer {
 public:
  BoardRenderer(const Rig& rig, BoardSpec board, double corner_noise_px, double pixel_noise);
  // The image camera `index` takes of the board, or an empty Mat if it cannot see the whole board
  // within 66 degrees of head-on (as project_board). `rng` draws the corner displacements and the
  // pixel noise.
  cv::Mat render(size_t index, const Eigen::Isometry3d& world_from_board, std::mt19937& rng) const;

 private:
  const Rig& rig_;
  BoardSpec board_;
  double corner_noise_px_;
  double pixel_noise_;
  std::vector<cv::Mat> normalised_;  // per camera: CV_64FC2 undistorted coords of pixel centres
};

// Renders the plan lazily, instant by instant; cameras that cannot see the printed face deliver
// no image.
class SyntheticViewProvider final : public ViewProvider {
 public:
  SyntheticViewProvider(const Rig& rig, const BoardRenderer& renderer,
                        std::vector<PlannedView> plan, unsigned seed);
  bool next(CaptureInstant& out) override;
  std::string describe() const override { return "synthetic capture"; }

 private:
  const Rig& rig_;
  const BoardRenderer& renderer_;
  std::vector<PlannedView> plan_;
  size_t cursor_ = 0;
  std::mt19937 rng_;
};

}  // namespace hullpose::calibrate::testing

namespace hullpose::calibrate::testing {

// How far a calibrated camera is from the truth, in issue 9's terms.
struct CameraError {
  int id = 0;
  double fx_pct = 0, fy_pct = 0;  // signed
  double cx_px = 0, cy_px = 0;    // signed
  double centre_mm = 0;
  double angle_deg = 0;
};

// A calibrated rig against the truth: every camera as written (world frame included), and the
// same after the rigid motion that best maps the calibrated rig onto the truth (camera centres,
// Umeyama): `gauge` errors are that motion (a wrong world frame moves all cameras together),
// `relative` errors what is left (the cameras' geometry among themselves).
struct RigError {
  std::vector<CameraError> absolute;
  std::vector<CameraError> relative;
  Eigen::Isometry3d truth_from_calibrated = Eigen::Isometry3d::Identity();  // the motion
  double gauge_angle_deg = 0;
  double gauge_tilt_deg = 0;       // of the z axis
  double gauge_mean_shift_mm = 0;  // mean distance the motion moves the true camera centres
  // Worst over cameras of each measure (intrinsics as magnitudes); id -1.
  CameraError worst(bool relative_frame = false) const;
};

RigError compare_rigs(const Rig& truth, const Rig& calibrated);

// Issue 9's tolerances: focal lengths within 0.5 %, principal point within 2 px, centre within
// 5 mm, orientation within 0.2 degrees.
bool meets_issue_tolerances(const CameraError& e);
std::ostream& operator<<(std::ostream& out, const CameraError& e);

// Renders `plan` with `corner_noise_px` RMS corner noise (2 grey levels of pixel noise), seeded,
// and detects the board in every image (OpenCV's detector, several images at once).
std::vector<Detection> render_and_detect(const Rig& rig, const BoardSpec& board,
                                         const std::vector<PlannedView>& plan,
                                         double corner_noise_px, unsigned seed);

}  // namespace hullpose::calibrate::testing
