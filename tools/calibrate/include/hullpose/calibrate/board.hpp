#pragma once
// The checkerboard target and its detection in one image.
#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hullpose::calibrate {

// A checkerboard of (cols + 1) x (rows + 1) squares, i.e. cols x rows inner corners. Board frame:
// x along a row of corners, y down the columns, z = x cross y (pointing into the board, away from
// a viewer of the printed face); corner (i, j) sits at (i, j, 0) * square_mm, row by row, x
// fastest (object_points()). The square between corners (0,0) and (1,1) is black (as in OpenCV's
// pattern, whose top-left square is black); with one side even and the other odd (e.g. 9 x 6)
// that fixes the corner order however the board is turned.
struct BoardSpec {
  int cols = 9;
  int rows = 6;
  double square_mm = 100;
  // Detection: on images under 1000 px wide, when the fast searches miss, also run the
  // exhaustive, accurate search (at double and full size). It finds boards of a few pixels a
  // square that the fast one misses, at seconds per image that holds no board.
  bool exhaustive_search = false;

  int corner_count() const { return cols * rows; }
  cv::Size pattern_size() const { return {cols, rows}; }
  std::vector<cv::Point3f> object_points() const;
  Eigen::Vector3d corner_mm(int index) const;
  // Centre of the inner-corner grid, board frame.
  Eigen::Vector3d centre_mm() const;
  // Throws hullpose::Error on a board the detector cannot handle.
  void validate() const;
};

// The board's inner corners in detector order, sub-pixel (cv::findChessboardCornersSB), or an
// empty vector if the whole board was not found. `image` is 8-bit grey or BGR.
std::vector<cv::Point2f> detect_board(const cv::Mat& image, const BoardSpec& board);

// Why detect_board() found nothing in an image of `image` size: what was searched for and how,
// for the tool's messages.
std::string board_search_summary(const BoardSpec& board, cv::Size image);

}  // namespace hullpose::calibrate
