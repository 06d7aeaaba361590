#include "hullpose/calibrate/board.hpp"

#include <algorithm>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

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
  HULLPOSE_THROW_UNLESS(
      cols >= 3 && rows >= 3 && cols <= 64 && rows <= 64,
      "board: " << cols << "x" << rows << " inner corners; need 3..64 on each side");
  HULLPOSE_THROW_UNLESS(!symmetric() || corners_marked,
                        "board: " << cols << "x" << rows
                                  << " inner corners is symmetric under a half turn; use one even "
                                     "and one odd side (e.g. 9x6) so corner order is unambiguous, "
                                     "or mark its corners by hand (--corners)");
  HULLPOSE_THROW_UNLESS(square_mm > 0 && square_mm < 10000,
                        "board: square size " << square_mm << " mm must be in (0, 10000)");
}

namespace {

// The detector orders corners by their layout in the image, not on the board: the same board
// seen by two cameras can come back mirrored or turned by half a turn. Restore board order:
// seen from the printed side, board x then y turn clockwise in the image (x right, y down), and
// the square between corners 0, 1, cols and cols + 1 is black, which tells a half turn apart
// because one side is even and the other odd.
void to_board_order(std::vector<cv::Point2f>& corners, const cv::Mat& grey,
                    const BoardSpec& board) {
  const int cols = board.cols, rows = board.rows;
  auto at = [&](int i, int j) -> cv::Point2f& {
    return corners[static_cast<size_t>(j * cols + i)];
  };
  const cv::Point2f ex = at(1, 0) - at(0, 0), ey = at(0, 1) - at(0, 0);
  if (ex.cross(ey) < 0)
    for (int j = 0; j < rows; ++j) std::reverse(&at(0, j), &at(0, j) + cols);
  // Mean brightness of the squares that should be black minus those that should be white.
  double should_be_black = 0, should_be_white = 0;
  for (int j = 0; j + 1 < rows; ++j)
    for (int i = 0; i + 1 < cols; ++i) {
      const cv::Point2f centre =
          0.25f * (at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1));
      cv::Mat patch;
      cv::getRectSubPix(grey, cv::Size(3, 3), centre, patch, CV_32F);
      ((i + j) % 2 == 0 ? should_be_black : should_be_white) += cv::mean(patch)[0];
    }
  if (should_be_black > should_be_white) std::reverse(corners.begin(), corners.end());
}

cv::Mat grey_of(const cv::Mat& image) {
  cv::Mat grey;
  if (image.channels() == 3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else
    grey = image;
  HULLPOSE_ASSERT(grey.type() == CV_8UC1);
  return grey;
}

// The smallest distance between neighbouring corners of a grid in board order.
double corner_spacing(const std::vector<cv::Point2f>& corners, const BoardSpec& board) {
  double spacing = std::numeric_limits<double>::infinity();
  for (int j = 0; j < board.rows; ++j)
    for (int i = 0; i < board.cols; ++i) {
      const cv::Point2f& p = corners[static_cast<size_t>(j * board.cols + i)];
      if (i + 1 < board.cols)
        spacing =
            std::min(spacing, cv::norm(corners[static_cast<size_t>(j * board.cols + i + 1)] - p));
      if (j + 1 < board.rows)
        spacing =
            std::min(spacing, cv::norm(corners[static_cast<size_t>((j + 1) * board.cols + i)] - p));
    }
  return spacing;
}

// cornerSubPix with a window that stays inside the four squares around a corner.
void refine_corners(const cv::Mat& grey, const BoardSpec& board,
                    std::vector<cv::Point2f>& corners) {
  const int half = std::clamp(static_cast<int>(0.35 * corner_spacing(corners, board)), 2, 8);
  cv::cornerSubPix(grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-3));
}

}  // namespace

std::vector<cv::Point2f> detect_board(const cv::Mat& image, const BoardSpec& board) {
  if (board.symmetric()) return {};  // found or not, its order would be a guess
  const cv::Mat grey = grey_of(image);
  std::vector<cv::Point2f> corners;
  // SB (Duda & Frese's localized Radon detector) finds the board robustly; its own corner
  // positions are off by ~0.2 px RMS (0.15 px with CALIB_CB_ACCURACY, which costs 3x the time),
  // errors that vary smoothly over a view and bias the principal point by pixels. cornerSubPix
  // (the gradient-orthogonality refinement) brings them to ~0.07 px on rendered boards.
  // Finding the board first on a half-size image costs a quarter of the time (the refinement
  // below restores full accuracy); small images and misses there get the full-size search.
  bool found = false;
  if (grey.cols >= 640 && grey.rows >= 480) {
    cv::Mat half;
    cv::pyrDown(grey, half);
    found = cv::findChessboardCornersSB(half, board.pattern_size(), corners,
                                        cv::CALIB_CB_NORMALIZE_IMAGE);
    // Pixel centres sit at integer coordinates in both images: half-size x is full-size 2x + 0.5.
    for (auto& p : corners) p = 2.0f * p + cv::Point2f(0.5f, 0.5f);
  }
  if (!found)
    found = cv::findChessboardCornersSB(grey, board.pattern_size(), corners,
                                        cv::CALIB_CB_NORMALIZE_IMAGE);
  // A board only a few pixels a square (far away, or lying on the floor seen from the side in a
  // small image): the detector's kernels need more pixels, so search at twice the size; last, if
  // asked for, the exhaustive search with sub-pixel accuracy at both sizes. That finds boards the
  // fast search misses (the Utrecht floor board: ~10 px squares seen edge-on, XviD-blurred: 2 of
  // its 4 cameras) at several times the cost.
  if (!found && grey.cols < 1000) {
    cv::Mat twice;
    cv::pyrUp(grey, twice);
    const int exhaustive =
        cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY;
    found = cv::findChessboardCornersSB(twice, board.pattern_size(), corners,
                                        cv::CALIB_CB_NORMALIZE_IMAGE) ||
            (board.exhaustive_search &&
             cv::findChessboardCornersSB(twice, board.pattern_size(), corners, exhaustive));
    // Double-size x is full-size 2x + 0.5 (pixel centres at integers in both).
    for (auto& p : corners) p = 0.5f * (p - cv::Point2f(0.5f, 0.5f));
    if (!found && board.exhaustive_search)
      found = cv::findChessboardCornersSB(grey, board.pattern_size(), corners, exhaustive);
  }
  if (!found || static_cast<int>(corners.size()) != board.corner_count()) return {};
  refine_corners(grey, board, corners);
  to_board_order(corners, grey, board);
  return corners;
}

std::vector<cv::Point2f> corners_from_marks(const cv::Mat& image, const BoardSpec& board,
                                            const MarkedCorners& marks) {
  const cv::Mat grey = grey_of(image);
  const cv::Rect inside(0, 0, grey.cols, grey.rows);
  for (const cv::Point2f& m : marks)
    HULLPOSE_THROW_UNLESS(inside.contains(m), "marked corner (" << m.x << ", " << m.y
                                                                << ") is outside the " << grey.cols
                                                                << "x" << grey.rows << " image");
  // Board order turns one way all round (either way: a board seen from behind is mirrored).
  int turns = 0;
  for (size_t k = 0; k < 4; ++k) {
    const cv::Point2f a = marks[(k + 1) % 4] - marks[k],
                      b = marks[(k + 2) % 4] - marks[(k + 1) % 4];
    turns += a.cross(b) > 0 ? 1 : a.cross(b) < 0 ? -1 : 0;
  }
  HULLPOSE_THROW_UNLESS(std::abs(turns) == 4,
                        "the four marked corners are not a convex quadrilateral in board order "
                        "(corner (0, 0), (cols-1, 0), (cols-1, rows-1), (0, rows-1))");
  const std::vector<cv::Point3f> object = board.object_points();
  std::vector<cv::Point2f> plane(object.size());
  for (size_t k = 0; k < object.size(); ++k) plane[k] = {object[k].x, object[k].y};
  const auto c = static_cast<size_t>(board.cols), r = static_cast<size_t>(board.rows);
  const std::vector<cv::Point2f> outline = {plane[0], plane[c - 1], plane[r * c - 1],
                                            plane[(r - 1) * c]};
  cv::Mat h =
      cv::getPerspectiveTransform(outline, std::vector<cv::Point2f>(marks.begin(), marks.end()));
  std::vector<cv::Point2f> corners;
  cv::perspectiveTransform(plane, corners, h);
  refine_corners(grey, board, corners);
  // Again from the homography of every refined corner: marks a few pixels off put the first
  // prediction of the middle corners further off than the refinement reaches.
  h = cv::findHomography(plane, corners);
  HULLPOSE_THROW_UNLESS(!h.empty(), "the refined corners fit no homography");
  cv::perspectiveTransform(plane, corners, h);
  refine_corners(grey, board, corners);
  // Perspective and lens distortion bend the grid's rows and columns smoothly; a corner that
  // refined onto something else (marks that do not outline the board) sits off the line of its
  // two neighbours by about a square. Blurred boards of a few pixels a square refine to within
  // a pixel or two of that line, hence the loose bound: half the smallest square.
  const double spacing = corner_spacing(corners, board);
  auto at = [&](size_t i, size_t j) { return corners[j * c + i]; };
  for (size_t j = 0; j < r; ++j)
    for (size_t i = 0; i < c; ++i) {
      // Distance from the midpoint of its two neighbours along a row or a column.
      double off = 0;
      if (i > 0 && i + 1 < c) off = cv::norm(0.5f * (at(i - 1, j) + at(i + 1, j)) - at(i, j));
      if (j > 0 && j + 1 < r)
        off = std::max(off, cv::norm(0.5f * (at(i, j - 1) + at(i, j + 1)) - at(i, j)));
      HULLPOSE_THROW_UNLESS(off <= spacing / 2,
                            "the marks do not outline the board: refined corner ("
                                << i << ", " << j << ") is " << off
                                << " px off the line of its neighbours (squares are " << spacing
                                << " px or more)");
    }
  return corners;
}

}  // namespace hullpose::calibrate

namespace hullpose::calibrate {

std::string board_search_summary(const BoardSpec& board, cv::Size image) {
  std::ostringstream s;
  if (board.symmetric())
    return "not searched: a symmetric board's corner order is known only from marks (--corners)";
  s << "no complete grid of " << board.cols << "x" << board.rows
    << " inner corners found (cv::findChessboardCornersSB";
  if (image.width >= 640 && image.height >= 480) s << " at half size,";
  s << " at full size";
  if (image.width < 1000) s << ", at double size";
  if (image.width < 1000 && board.exhaustive_search) s << ", exhaustively at double and full size";
  s << "); every inner corner must be in view, unoccluded, with squares of a few pixels or more";
  if (image.width < 1000 && !board.exhaustive_search)
    s << " (--exhaustive-search finds smaller, blurred boards, slowly)";
  return s.str();
}

}  // namespace hullpose::calibrate
