#pragma once
// The whole calibration: board detection with live feedback as instants arrive, then intrinsics
// per camera, linking the cameras through shared board views, a bundle adjustment over every
// observation, the world frame from the board lying on the floor and the capture volume.
#include <iosfwd>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "hullpose/calibrate/board.hpp"
#include "hullpose/calibrate/intrinsics.hpp"
#include "hullpose/calibrate/view_provider.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::calibrate {

struct CalibrationOptions {
  BoardSpec board;
  IntrinsicsOptions intrinsics;
  std::string rig_id = "calibrated";
  // Instants whose board lies printed face up on the floor. The first sets the origin (under the
  // centre of its corner grid) and the x axis (along its rows of corners); all of them together
  // set the floor plane (z = 0, z up). Boards spread over the floor pin the plane's tilt far
  // better than one board's own tilt does (0.06 degrees of tilt moves a camera 4 m away by 4 mm).
  std::vector<std::string> floor_views = {"floor"};
  double board_thickness_mm = 0;
  bool refine_intrinsics = true;  // in the bundle adjustment
  // Cameras whose intrinsics are known (by id, from another calibration: --intrinsics RIG.yaml):
  // only their board poses are estimated, and the bundle adjustment keeps their intrinsics.
  std::map<int, CameraModel> known_intrinsics;
  // Board corners marked by hand, by (camera id, view) (--corners FILE): those images are not
  // searched but refined from the marks. With marks, board.corners_marked allows a symmetric
  // board, and its unmarked images are skipped (no detector can order it).
  std::map<std::pair<int, std::string>, MarkedCorners> marked_corners;
  int volume_min_cameras = 0;  // 0: all cameras
  double max_rms_px = 2.0;     // a rig worse than this is refused, not written
};

struct CameraReport {
  int id = 0;
  int images = 0;
  int boards_found = 0;
  int views_kept = 0;
  std::vector<std::string> rejected_views;
  int shared_views = 0;         // kept views that another camera saw too
  double coverage = 0;          // fraction of the image covered by kept boards
  double intrinsic_rms_px = 0;  // cv::calibrateCamera alone
  double rig_rms_px = 0;        // after the bundle adjustment
};

struct CalibrationResult {
  Rig rig;
  int floor_boards = 0;  // floor views that set the world frame
  std::vector<CameraReport> cameras;
  double rms_px = 0;
  double initial_rms_px = 0;  // of the chained rig, before the bundle adjustment
  int iterations = 0;
  int corners = 0;
};

class RigCalibrator {
 public:
  // Live feedback (one line per camera image) goes to `feedback` if given.
  explicit RigCalibrator(CalibrationOptions options, std::ostream* feedback = nullptr);

  // Detects the board in every image of the instant.
  void add(const CaptureInstant& instant);
  // Same, with corners already detected (empty: no board).
  void add_detection(const std::string& view, int camera_id, cv::Size image_size,
                     std::vector<cv::Point2f> corners);
  // Reads the provider to its end.
  void add_all(ViewProvider& provider);

  // Throws hullpose::Error naming the cameras at fault: too few or degenerate views, no floor
  // board, cameras not linked to the rig, an inconsistent result, marks for an image that never
  // came.
  CalibrationResult solve() const;

 private:
  int view_index(const std::string& view);

  CalibrationOptions options_;
  std::ostream* feedback_;
  std::map<int, IntrinsicsCalibrator> cameras_;
  std::vector<std::string> views_;
  std::map<std::string, int> view_index_;
  std::set<std::pair<int, std::string>> marks_used_;
};

void print_report(std::ostream& out, const CalibrationResult& result);

}  // namespace hullpose::calibrate
