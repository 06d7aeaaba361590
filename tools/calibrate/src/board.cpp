#include "hullpose/calibrate/board.hpp"

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::calibrate {

std::vector<cv::Point3f> BoardSpec::object_points() const {
  std::vector<cv::Point3f> pts;
  pts.reserve(static_cast<size_t>(corner_count()));
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i)
      pts.emplace_back(static_cast<float>(i * square_mm), static_cast<float>(j * square_mm), 0.0f);
  return pts;
}

Eigen::Vector3d BoardSpec::corner_mm(int index) const {
  return {(index % cols) * square_mm, (index / cols) * square_mm, 0.0};
}

Eigen::Vector3d BoardSpec::centre_mm() const {
  return {0.5 * (cols - 1) * square_mm, 0.5 * (rows - 1) * square_mm, 0.0};
}

void BoardSpec::validate() const {
  HULLPOSE_THROW_UNLESS(cols >= 3 && rows >= 3 && cols <= 64 && rows <= 64,
                        "board: " << cols << "x" << rows
                                  << " inner corners; need 3..64 on each side");
  HULLPOSE_THROW_UNLESS((cols + rows) % 2 == 1,
                        "board: " << cols << "x" << rows
                                  << " inner corners is symmetric under a half turn; use one even "
                                     "and one odd side (e.g. 9x6) so corner order is unambiguous");
  HULLPOSE_THROW_UNLESS(square_mm > 0 && square_mm < 10000,
                        "board: square size " << square_mm << " mm must be in (0, 10000)");
}

namespace {

// The detector orders corners by their layout in the image, not on the board: the same board
// seen by two cameras can come back mirrored or turned by half a turn. Restore board order:
// seen from the printed side, board x then y turn clockwise in the image (x right, y down), and
// the square between corners 0, 1, cols and cols + 1 is black, which tells a half turn apart
// because one side is even and the other odd.
void to_board_order(std::vector<cv::Point2f>& corners, const cv::Mat& grey, const BoardSpec& board) {
  const int cols = board.cols, rows = board.rows;
  auto at = [&](int i, int j) -> cv::Point2f& { return corners[static_cast<size_t>(j * cols + i)]; };
  const cv::Point2f ex = at(1, 0) - at(0, 0), ey = at(0, 1) - at(0, 0);
  if (ex.cross(ey) < 0)
    for (int j = 0; j < rows; ++j) std::reverse(&at(0, j), &at(0, j) + cols);
  // Mean brightness of the squares that should be black minus those that should be white.
  double should_be_black = 0, should_be_white = 0;
  for (int j = 0; j + 1 < rows; ++j)
    for (int i = 0; i + 1 < cols; ++i) {
      const cv::Point2f centre = 0.25f * (at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1));
      cv::Mat patch;
      cv::getRectSubPix(grey, cv::Size(3, 3), centre, patch, CV_32F);
      ((i + j) % 2 == 0 ? should_be_black : should_be_white) += cv::mean(patch)[0];
    }
  if (should_be_black > should_be_white) std::reverse(corners.begin(), corners.end());
}

}  // namespace

std::vector<cv::Point2f> detect_board(const cv::Mat& image, const BoardSpec& board) {
  cv::Mat grey;
  if (image.channels() == 3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else
    grey = image;
  HULLPOSE_ASSERT(grey.type() == CV_8UC1);
  std::vector<cv::Point2f> corners;
  // SB (Duda & Frese's localized Radon detector) is both more robust than the classic detector
  // and sub-pixel accurate by itself; ACCURACY refines on an upsampled image.
  const bool found = cv::findChessboardCornersSB(
      grey, board.pattern_size(), corners, cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_ACCURACY);
  if (!found || static_cast<int>(corners.size()) != board.corner_count()) return {};
  to_board_order(corners, grey, board);
  return corners;
}

}  // namespace hullpose::calibrate
