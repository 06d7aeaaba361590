#pragma once
// Synthetic calibration captures for the tests: a rig like the thesis lab (7 cameras in a ring,
// one on the ceiling, 800x600, realistic distortion), a capture plan (close-ups per camera,
// boards spread over the volume seen by several cameras, the board on the floor) and a renderer
// that draws the board through the exact camera model (anti-aliased by 4x4 supersampling) with
// every inner corner displaced by seeded Gaussian noise, so detected corners carry a known noise
// level. Pixel centres sit at integer coordinates, as in OpenCV.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
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

// close_ups per camera, `shared` boards in the middle, and "floor". Names sort in plan order.
std::vector<PlannedView> make_capture_plan(const Rig& rig, const BoardSpec& board, int close_ups,
                                           int shared, unsigned seed);

// The board on the floor, printed face up, its corner-grid centre at the world origin.
Eigen::Isometry3d floor_board_pose(const BoardSpec& board);

// The corners camera `c` would detect of a board at `world_from_board`, with Gaussian noise of
// `noise_px` per axis; empty if the printed face is not seen head-on enough (within 70 degrees)
// or the board is not wholly inside the image. The corner-level stand-in for render + detect.
std::vector<cv::Point2f> project_board(const CameraModel& c, const BoardSpec& board,
                                       const Eigen::Isometry3d& world_from_board, double noise_px,
                                       std::mt19937& rng);

class BoardRenderer {
 public:
  BoardRenderer(const Rig& rig, BoardSpec board, double corner_noise_px, double pixel_noise);
  // The image camera `index` takes of the board, or an empty Mat if it cannot see the whole board
  // within 70 degrees of head-on. `rng` draws the corner displacements and the pixel noise.
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
