#include "hullpose/calibrate/intrinsics.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::calibrate {
namespace {

// Coverage is tracked on a coarse grid: the fraction of cells some board has covered.
constexpr int kCoverageCols = 40;
constexpr int kCoverageRows = 30;
constexpr int kMaxRejectRounds = 5;
// A corner this many times the camera's RMS error off is a detection error, not noise (for
// Gaussian noise the odds are below 1e-15).
constexpr double kCornerOutlierFactor = 6.0;
// Above these one-sigma uncertainties the estimate is not trusted (views too alike).
constexpr double kMaxFocalSigmaFraction = 0.01;
constexpr double kMaxCentreSigmaPx = 5.0;

// Marks the grid cells under the board's outline (its four outer corners).
void mark_coverage(cv::Mat& grid, const std::vector<cv::Point2f>& corners, const BoardSpec& board,
                   cv::Size image_size) {
  const int c = board.cols, r = board.rows;
  const double sx = static_cast<double>(grid.cols) / image_size.width;
  const double sy = static_cast<double>(grid.rows) / image_size.height;
  std::vector<cv::Point> quad;
  for (int idx : {0, c - 1, r * c - 1, (r - 1) * c}) {
    const auto& p = corners[static_cast<size_t>(idx)];
    quad.emplace_back(static_cast<int>(std::lround(static_cast<double>(p.x) * sx)),
                      static_cast<int>(std::lround(static_cast<double>(p.y) * sy)));
  }
  cv::fillConvexPoly(grid, quad, cv::Scalar(255));
}

double covered_fraction(const cv::Mat& grid) {
  return static_cast<double>(cv::countNonZero(grid)) / static_cast<double>(grid.total());
}

double median(std::vector<double> v) {
  HULLPOSE_ASSERT(!v.empty());
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

Eigen::Isometry3d isometry(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  cv::cv2eigen(R, r);
  cv::cv2eigen(tvec.reshape(1, 3), t);
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = r;
  out.translation() = t;
  return out;
}

}  // namespace

double view_rms_px(const CameraModel& camera, const Eigen::Isometry3d& cam_from_board,
                   const BoardSpec& board, const std::vector<cv::Point2f>& corners) {
  HULLPOSE_ASSERT(static_cast<int>(corners.size()) == board.corner_count());
  CameraModel c = camera;
  c.R = cam_from_board.linear();
  c.t = cam_from_board.translation();
  double sum = 0;
  for (int i = 0; i < board.corner_count(); ++i) {
    const auto p = c.project(board.corner_mm(i));
    if (!p) return std::numeric_limits<double>::infinity();
    const auto& q = corners[static_cast<size_t>(i)];
    sum += (*p - Eigen::Vector2d(q.x, q.y)).squaredNorm();
  }
  return std::sqrt(sum / board.corner_count());
}

IntrinsicsCalibrator::IntrinsicsCalibrator(int camera_id, BoardSpec board,
                                           IntrinsicsOptions options)
    : camera_id_(camera_id), board_(board), options_(options) {
  board_.validate();
  HULLPOSE_THROW_UNLESS(options_.min_views >= 3, "intrinsics: min_views must be at least 3");
}

ViewFeedback IntrinsicsCalibrator::add_view(const std::string& view, cv::Size image_size,
                                            std::vector<cv::Point2f> corners) {
  if (image_size_.empty()) {
    image_size_ = image_size;
    coverage_ = cv::Mat::zeros(kCoverageRows, kCoverageCols, CV_8UC1);
  }
  HULLPOSE_THROW_UNLESS(image_size == image_size_,
                        "camera " << camera_id_ << ", view '" << view << "': image is "
                                  << image_size.width << "x" << image_size.height
                                  << " but earlier ones were " << image_size_.width << "x"
                                  << image_size_.height);
  ++seen_;
  ViewFeedback fb;
  fb.camera_id = camera_id_;
  fb.view = view;
  fb.found = !corners.empty();
  if (fb.found) {
    HULLPOSE_ASSERT(static_cast<int>(corners.size()) == board_.corner_count());
    mark_coverage(coverage_, corners, board_, image_size_);
    views_.push_back({view, std::move(corners)});
    // Re-estimate once there are enough views and whenever their number grew by half: the
    // feedback stays cheap while the estimate follows the capture.
    if (options_.live_estimates && views_.size() >= static_cast<size_t>(options_.min_views) &&
        (!live_ || views_.size() * 2 >= live_views_ * 3)) {
      std::vector<const BoardView*> all;
      for (const auto& v : views_) all.push_back(&v);
      std::vector<cv::Mat> rvecs, tvecs;
      double rms = 0;
      try {
        live_ = run_opencv(all, rvecs, tvecs, live_errors_, rms);
        check_determined(*live_, all.size());
        live_views_ = views_.size();
      } catch (const Error&) {
        live_.reset();  // degenerate so far; calibrate() says why
      }
    }
    if (live_) {
      cv::Mat rvec, tvec;
      const auto& v = views_.back();
      if (cv::solvePnP(board_.object_points(), v.corners, live_->K, live_->dist, rvec, tvec, false,
                       cv::SOLVEPNP_IPPE)) {
        CameraModel cam;
        cam.fx = live_->K.at<double>(0, 0);
        cam.fy = live_->K.at<double>(1, 1);
        cam.cx = live_->K.at<double>(0, 2);
        cam.cy = live_->K.at<double>(1, 2);
        for (int i = 0; i < 5; ++i) cam.dist[static_cast<size_t>(i)] = live_->dist.at<double>(i);
        fb.view_rms_px = view_rms_px(cam, isometry(rvec, tvec), board_, v.corners);
        fb.outlier = *fb.view_rms_px > std::max(options_.outlier_factor * median(live_errors_),
                                                options_.outlier_floor_px);
      }
    }
  }
  fb.views_kept = static_cast<int>(views_.size());
  fb.coverage = covered_fraction(coverage_);
  return fb;
}

IntrinsicsCalibrator::Estimate IntrinsicsCalibrator::run_opencv(
    const std::vector<const BoardView*>& views, std::vector<cv::Mat>& rvecs,
    std::vector<cv::Mat>& tvecs, std::vector<double>& per_view, double& rms) const {
  const std::vector<cv::Point3f> object = board_.object_points();
  std::vector<std::vector<cv::Point3f>> objects(views.size(), object);
  std::vector<std::vector<cv::Point2f>> images;
  for (const auto* v : views) images.push_back(v->corners);
  Estimate e;
  cv::Mat std_intrinsics, std_extrinsics, errors;
  int flags = 0;
  if (!options_.estimate_k3) flags |= cv::CALIB_FIX_K3;
  // OpenCV's Levenberg-Marquardt solves each step by an SVD over all views' parameters, which
  // costs most of a calibration with 30 views; stopping at a relative change of 1e-6 (fx to
  // ~0.001 px) instead of 1e-9 halves the time and changed no result the tests see (the bundle
  // adjustment refines these anyway).
  try {
    rms = cv::calibrateCamera(
        objects, images, image_size_, e.K, e.dist, rvecs, tvecs, std_intrinsics, std_extrinsics,
        errors, flags, cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 1e-6));
  } catch (const cv::Exception& ex) {
    HULLPOSE_THROW("camera " << camera_id_ << ": intrinsic calibration failed on " << views.size()
                             << " views: " << ex.err);
  }
  HULLPOSE_THROW_UNLESS(cv::checkRange(e.K) && cv::checkRange(e.dist),
                        "camera " << camera_id_ << ": intrinsic calibration diverged");
  per_view.assign(errors.begin<double>(), errors.end<double>());
  // Per-view errors, like the returned RMS, are RMS distances (2D) per corner.
  e.sigma = {std_intrinsics.at<double>(0), std_intrinsics.at<double>(1),
             std_intrinsics.at<double>(2), std_intrinsics.at<double>(3)};
  e.normals.clear();
  for (const auto& r : rvecs)
    e.normals.push_back(isometry(r, cv::Mat::zeros(3, 1, CV_64F)).linear().col(2));
  return e;
}

void IntrinsicsCalibrator::check_determined(const Estimate& e, size_t views) const {
  // Zhang's method needs board orientations that are not all parallel.
  double spread = 0;
  for (size_t a = 0; a < e.normals.size(); ++a)
    for (size_t b = a + 1; b < e.normals.size(); ++b)
      spread = std::max(spread, std::acos(std::clamp(e.normals[a].dot(e.normals[b]), -1.0, 1.0)));
  spread *= 180.0 / M_PI;
  HULLPOSE_THROW_UNLESS(
      spread >= options_.min_tilt_spread_deg,
      "camera " << camera_id_ << ": all " << views
                << " board views are nearly parallel (orientations differ by at most " << spread
                << " deg, need " << options_.min_tilt_spread_deg
                << "); tilt the board in different directions");
  const double fx = e.K.at<double>(0, 0), fy = e.K.at<double>(1, 1);
  const auto [sfx, sfy, scx, scy] = e.sigma;
  HULLPOSE_THROW_UNLESS(
      sfx <= kMaxFocalSigmaFraction * fx && sfy <= kMaxFocalSigmaFraction * fy &&
          scx <= kMaxCentreSigmaPx && scy <= kMaxCentreSigmaPx,
      "camera " << camera_id_ << ": the " << views
                << " board views leave the intrinsics poorly determined (sigma fx " << sfx
                << ", fy " << sfy << ", cx " << scx << ", cy " << scy
                << " px); add views with the board tilted and near the image corners");
}

IntrinsicsResult IntrinsicsCalibrator::calibrate() const {
  HULLPOSE_THROW_UNLESS(seen_ > 0, "camera " << camera_id_ << ": no images");
  HULLPOSE_THROW_UNLESS(!views_.empty(),
                        "camera " << camera_id_ << ": no checkerboard (" << board_.cols << "x"
                                  << board_.rows << " inner corners) found in any of its " << seen_
                                  << "images: " << board_search_summary(board_, image_size_));
  HULLPOSE_THROW_UNLESS(static_cast<int>(views_.size()) >= options_.min_views,
                        "camera " << camera_id_ << ": board found in only " << views_.size()
                                  << " of " << seen_ << " images; need at least "
                                  << options_.min_views);
  std::vector<const BoardView*> kept;
  for (const auto& v : views_) kept.push_back(&v);
  IntrinsicsResult result;
  std::vector<cv::Mat> rvecs, tvecs;
  std::vector<double> errors;
  double rms = 0;
  Estimate e;
  for (int round = 0;; ++round) {
    e = run_opencv(kept, rvecs, tvecs, errors, rms);
    const double threshold =
        std::max(options_.outlier_factor * median(errors), options_.outlier_floor_px);
    // A detector that misplaces one corner by pixels barely moves its view's RMS, yet that corner
    // pulls the whole rig: a view is also rejected for a single corner far beyond the noise.
    const double corner_threshold = std::max(kCornerOutlierFactor * rms, options_.outlier_floor_px);
    const std::vector<cv::Point3f> object = board_.object_points();
    std::vector<cv::Point2f> projected;
    std::vector<const BoardView*> next;
    for (size_t i = 0; i < kept.size(); ++i) {
      cv::projectPoints(object, rvecs[i], tvecs[i], e.K, e.dist, projected);
      double worst = 0;
      for (size_t k = 0; k < projected.size(); ++k)
        worst = std::max(worst, static_cast<double>(cv::norm(projected[k] - kept[i]->corners[k])));
      if (errors[i] <= threshold && worst <= corner_threshold)
        next.push_back(kept[i]);
      else
        result.rejected.push_back(kept[i]->view);
    }
    if (next.size() == kept.size() || round == kMaxRejectRounds) break;
    HULLPOSE_THROW_UNLESS(
        static_cast<int>(next.size()) >= options_.min_views,
        "camera " << camera_id_ << ": only " << next.size() << " of " << views_.size()
                  << " board views are consistent (the others have reprojection errors above "
                  << threshold << " px); need at least " << options_.min_views);
    kept = std::move(next);
  }
  check_determined(e, kept.size());
  CameraModel& cam = result.camera;
  cam.id = camera_id_;
  cam.name = "cam" + std::to_string(camera_id_);
  cam.width = image_size_.width;
  cam.height = image_size_.height;
  cam.fx = e.K.at<double>(0, 0);
  cam.fy = e.K.at<double>(1, 1);
  cam.cx = e.K.at<double>(0, 2);
  cam.cy = e.K.at<double>(1, 2);
  for (int i = 0; i < 5; ++i) cam.dist[static_cast<size_t>(i)] = e.dist.at<double>(i);
  result.rms_px = rms;
  cv::Mat cov = cv::Mat::zeros(kCoverageRows, kCoverageCols, CV_8UC1);
  for (size_t i = 0; i < kept.size(); ++i) {
    result.kept.push_back(*kept[i]);
    result.cam_from_board.push_back(isometry(rvecs[i], tvecs[i]));
    result.view_rms_px.push_back(errors[i]);
  }
  // Coverage of the kept views only.
  for (const auto* v : kept) mark_coverage(cov, v->corners, board_, image_size_);
  result.coverage = covered_fraction(cov);
  return result;
}

IntrinsicsResult IntrinsicsCalibrator::with_known(const CameraModel& known) const {
  HULLPOSE_THROW_UNLESS(!views_.empty(),
                        "camera " << camera_id_ << ": no checkerboard (" << board_.cols << "x"
                                  << board_.rows << " inner corners) found in any of its " << seen_
                                  << "images: " << board_search_summary(board_, image_size_));
  HULLPOSE_THROW_UNLESS(image_size_ == cv::Size(known.width, known.height),
                        "camera " << camera_id_ << ": images are " << image_size_.width << "x"
                                  << image_size_.height << ", the given intrinsics are for "
                                  << known.width << "x" << known.height);
  IntrinsicsResult result;
  result.camera = known;
  result.camera.id = camera_id_;
  result.camera.R.setIdentity();
  result.camera.t.setZero();
  cv::Mat K = (cv::Mat_<double>(3, 3) << known.fx, 0, known.cx, 0, known.fy, known.cy, 0, 0, 1);
  cv::Mat dist(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) dist.at<double>(i) = known.dist[static_cast<size_t>(i)];
  cv::Mat cov = cv::Mat::zeros(kCoverageRows, kCoverageCols, CV_8UC1);
  double sum2 = 0;
  size_t n = 0;
  // A view's board pose: the iterative solver (homography start, Levenberg-Marquardt), then LM
  // again; rms in px. Not IPPE: on a far floor board seen obliquely (tests/calibrate/
  // test_calibrate_known, camera 1) it returned the wrong one of its two planar solutions.
  auto pose_of = [&](const std::vector<cv::Point2f>& corners, Eigen::Isometry3d& pose) {
    cv::Mat rvec, tvec;
    if (!cv::solvePnP(board_.object_points(), corners, K, dist, rvec, tvec, false,
                      cv::SOLVEPNP_ITERATIVE))
      return std::numeric_limits<double>::infinity();
    cv::solvePnPRefineLM(board_.object_points(), corners, K, dist, rvec, tvec);
    pose = isometry(rvec, tvec);
    return view_rms_px(result.camera, pose, board_, corners);
  };
  for (const BoardView& view : views_) {
    Eigen::Isometry3d pose;
    const double e = pose_of(view.corners, pose);
    if (!std::isfinite(e)) {
      result.rejected.push_back(view.view);
      continue;
    }
    result.kept.push_back(view);
    result.cam_from_board.push_back(pose);
    result.view_rms_px.push_back(e);
    sum2 += e * e * static_cast<double>(view.corners.size());
    n += view.corners.size();
    mark_coverage(cov, view.corners, board_, image_size_);
  }
  HULLPOSE_THROW_UNLESS(!result.kept.empty(),
                        "camera " << camera_id_ << ": no board pose from the given intrinsics");
  result.rms_px = std::sqrt(sum2 / static_cast<double>(n));
  result.coverage = covered_fraction(cov);
  return result;
}

}  // namespace hullpose::calibrate
