#pragma once
// The checkerboard target and its detection in one image.
#include <Eigen/Core>
#include <array>
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
  // The corner order comes from hand-marked corners (MarkedCorners), so a board symmetric under a
  // half turn (both sides even, e.g. 8x6) is accepted; detect_board() never reads one.
  bool corners_marked = false;

  bool symmetric() const { return (cols + rows) % 2 == 0; }

  int corner_count() const { return cols * rows; }
  cv::Size pattern_size() const { return {cols, rows}; }
  std::vector<cv::Point3f> object_points() const;
  Eigen::Vector3d corner_mm(int index) const;
  // Centre of the inner-corner grid, board frame.
  Eigen::Vector3d centre_mm() const;
  // Throws hullpose::Error on a board the detector cannot handle.
  void validate() const;
};

// The board's inner corners in board order, sub-pixel (cv::findChessboardCornersSB), or an
// empty vector if the whole board was not found or is symmetric (its order unknown). `image` is
// 8-bit grey or BGR.
std::vector<cv::Point2f> detect_board(const cv::Mat& image, const BoardSpec& board);

// Four inner corners marked by hand in one image, in board order: corner (0, 0), then
// (cols - 1, 0), (cols - 1, rows - 1) and (0, rows - 1). For boards no detector finds (a few
// pixels a square, seen edge-on, blurred) and for symmetric ones, whose order only a person can
// tell.
using MarkedCorners = std::array<cv::Point2f, 4>;

// Every inner corner in board order from the four marks: predicted through the homography of
// the board plane and refined (cornerSubPix), then predicted again from all refined corners (so
// lens distortion between the marks is followed) and refined again. Marks a few pixels off are
// fine. Throws hullpose::Error when the marks do not outline the board: not a convex
// quadrilateral in board order, outside the image, or a corner that ends more than a third of
// a square from where the refined grid puts it.
std::vector<cv::Point2f> corners_from_marks(const cv::Mat& image, const BoardSpec& board,
                                            const MarkedCorners& marks);

// Why detect_board() found nothing in an image of `image` size: what was searched for and how,
// for the tool's messages.
std::string board_search_summary(const BoardSpec& board, cv::Size image);

}  // namespace hullpose::calibrate
