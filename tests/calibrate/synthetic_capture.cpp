#include "synthetic_capture.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <opencv2/core/utility.hpp>

#include "hullpose/common/check.hpp"

namespace hullpose::calibrate::testing {
namespace {

constexpr double kDeg = M_PI / 180.0;
// On the rendered boards the detector finds ~95 % of the boards seen up to 60 degrees from
// head-on and ~30 % of those between 60 and 70 (calibrate_sweep missed). Neither the renderer
// nor the corner-level stand-in shows a camera a board beyond 66 degrees: that spares the tests
// most misses (each costs 4x a hit's detection time) yet keeps the floor boards, which the ring
// cameras see at 60-65 degrees.
constexpr double kDetectedObliquityDeg = 66;

// Whether a camera sees the printed face of the board within kDetectedObliquityDeg.
bool seen_head_on_enough(const BoardSpec& board, const Eigen::Isometry3d& cam_from_board) {
  const Eigen::Vector3d centre = cam_from_board * board.centre_mm();
  return centre.z() > 0 && cam_from_board.linear().col(2).dot(centre.normalized()) >=
                               std::cos(kDetectedObliquityDeg * kDeg);
}

// Camera looking from `centre` at `target`, x right and y down in the image, z up in the world.
CameraModel look_at(int id, const Eigen::Vector3d& centre, const Eigen::Vector3d& target,
                    const Eigen::Vector3d& up, double roll) {
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  R = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R;
  CameraModel c;
  c.id = id;
  c.name = "cam" + std::to_string(id);
  c.width = 800;
  c.height = 600;
  c.R = R;
  c.t = -R * centre;
  return c;
}

Eigen::Isometry3d cam_pose(const CameraModel& c) {
  Eigen::Isometry3d cam_from_world = Eigen::Isometry3d::Identity();
  cam_from_world.linear() = c.R;
  cam_from_world.translation() = c.t;
  return cam_from_world;
}

// A board rotation whose printed face looks along `facing` (unit), turned by `spin` in its plane.
Eigen::Matrix3d facing_rotation(const Eigen::Vector3d& facing, double spin) {
  const Eigen::Vector3d z = -facing;  // board z points away from the viewers of the face
  Eigen::Vector3d helper =
      std::abs(z.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x0 = helper.cross(z).normalized();
  const Eigen::Vector3d y0 = z.cross(x0);
  Eigen::Matrix3d R;
  R.col(0) = x0;
  R.col(1) = y0;
  R.col(2) = z;
  return R * Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

bool board_inside(const CameraModel& c, const BoardSpec& board,
                  const Eigen::Isometry3d& world_from_board, double margin) {
  for (int i = 0; i < board.corner_count(); ++i) {
    // The outer squares and paper margin must be inside too: check a border one square out.
    for (double dx : {-1.5, 0.0, 1.5})
      for (double dy : {-1.5, 0.0, 1.5}) {
        const Eigen::Vector3d q = board.corner_mm(i) + board.square_mm * Eigen::Vector3d(dx, dy, 0);
        const auto p = c.project(world_from_board * q);
        if (!p || p->x() < margin || p->y() < margin || p->x() > c.width - margin ||
            p->y() > c.height - margin)
          return false;
      }
  }
  return true;
}

}  // namespace

Rig make_ring_rig(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Rig rig;
  rig.rig_id = "synthetic-ring";
  for (int k = 0; k < 8; ++k) {
    CameraModel c;
    if (k < 7) {
      const double a = 2 * M_PI * k / 7 + 3 * kDeg * u(rng);
      const Eigen::Vector3d centre(4000 * std::cos(a), 4000 * std::sin(a), 2000 + 100 * u(rng));
      // One draw per statement, in the order x86-64 GCC evaluated the arguments before (right to
      // left): argument order is unspecified, and the rig must be the same on every architecture.
      const double roll = 2 * kDeg * u(rng);
      const double tz = 900 + 100 * u(rng), ty = 100 * u(rng), tx = 100 * u(rng);
      c = look_at(k, centre, Eigen::Vector3d(tx, ty, tz), Eigen::Vector3d::UnitZ(), roll);
    } else {
      const double roll = 2 * kDeg * u(rng);
      const double ty = 100 * u(rng), tx = 100 * u(rng);
      const double ey = 50 * u(rng), ex = 50 * u(rng);
      c = look_at(k, Eigen::Vector3d(ex, ey, 3600), Eigen::Vector3d(tx, ty, 0),
                  Eigen::Vector3d::UnitX(), roll);
    }
    c.fx = 600 + 30 * u(rng);
    c.fy = c.fx * (1 + 0.004 * u(rng));
    c.cx = 400 + 10 * u(rng);
    c.cy = 300 + 10 * u(rng);
    c.dist = {-0.22 + 0.03 * u(rng), 0.06 + 0.02 * u(rng), 5e-4 * u(rng), 5e-4 * u(rng), 0.0};
    rig.cameras.push_back(c);
  }
  rig.volume.min_mm = Eigen::Vector3d(-1200, -1200, 0);
  rig.volume.max_mm = Eigen::Vector3d(1200, 1200, 2200);
  rig.validate();
  return rig;
}

Eigen::Isometry3d floor_board_pose(const BoardSpec& board) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  pose.translation() = -(pose.linear() * board.centre_mm());
  return pose;
}

std::vector<std::string> floor_view_names(const CapturePlan& plan) {
  std::vector<std::string> names{"floor"};
  for (int k = 2; k <= plan.floors; ++k) names.push_back("floor" + std::to_string(k));
  return names;
}

std::vector<PlannedView> make_capture_plan(const Rig& rig, const BoardSpec& board,
                                           const CapturePlan& options, unsigned seed) {
  const int close_ups = options.close_ups, shared = options.shared;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<PlannedView> plan;
  char name[64];
  // Close-ups: the board held 1.8-2.8 m in front of one camera (small enough in the image to
  // reach its corners), centred on a 3x3 grid of image positions, tilted 40-60 degrees every way
  // in turn: strong tilts pin the principal point and the focal length (a nearly fronto-parallel
  // board trades focal length against distance, and the principal point against rotation).
  for (const auto& c : rig.cameras) {
    const Eigen::Isometry3d world_from_cam = cam_pose(c).inverse();
    for (int v = 0; v < close_ups; ++v) {
      for (int attempt = 0; attempt < 200; ++attempt) {
        const double scale = attempt < 100 ? 1.0 : 0.5;  // fall back towards the centre
        const int cell = v % 9;
        const double jy = u(rng), jx = u(rng);  // y first: see make_ring_rig
        const Eigen::Vector2d target(
            c.width * (0.5 + scale * 0.32 * ((cell % 3) - 1) + 0.04 * jx),
            c.height * (0.5 + scale * 0.32 * ((cell / 3) - 1) + 0.04 * jy));
        const Eigen::Vector2d xn = c.undistort_pixel(target);
        const double dist = 1800 + 1000 * (0.5 + 0.5 * u(rng));
        const Eigen::Vector3d centre_cam = dist * Eigen::Vector3d(xn.x(), xn.y(), 1).normalized();
        const double tilt = (options.min_tilt_deg +
                             (options.max_tilt_deg - options.min_tilt_deg) * (0.5 + 0.5 * u(rng))) *
                            kDeg;
        const double axis_angle = M_PI / 4 * (v % 8) + 0.2 * u(rng);  // tilt every way in turn
        const Eigen::Vector3d axis(std::cos(axis_angle), std::sin(axis_angle), 0);
        Eigen::Isometry3d cam_from_board = Eigen::Isometry3d::Identity();
        cam_from_board.linear() =
            Eigen::AngleAxisd(tilt, axis).toRotationMatrix() *
            Eigen::AngleAxisd(0.4 * u(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
        cam_from_board.translation() = centre_cam - cam_from_board.linear() * board.centre_mm();
        const Eigen::Isometry3d pose = world_from_cam * cam_from_board;
        // The live feedback tells the operator when the camera misses the board: turned back
        // within the detector's reach.
        if (!board_inside(c, board, pose, 8) || !seen_head_on_enough(board, cam_from_board))
          continue;
        std::snprintf(name, sizeof name, "a%02d_close%02d", c.id, v);
        plan.push_back({name, pose});
        break;
      }
    }
  }
  // Boards spread over the volume (+-1.2 m, 0.6-1.6 m high), faces turned to every side and
  // upwards, so that each is seen by a few ring cameras and often by the ceiling camera; boards at
  // different distances from a camera separate its focal length from its distance.
  for (int v = 0; v < shared; ++v) {
    const double az = 2 * M_PI * v / shared + 10 * kDeg * u(rng);
    const double el = (25 + 25 * (0.5 + 0.5 * u(rng))) * kDeg;
    const Eigen::Vector3d facing(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el),
                                 std::sin(el));
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = facing_rotation(facing, 0.5 * u(rng));
    const double z = 1100 + 500 * u(rng), y = 1200 * u(rng), x = 1200 * u(rng);  // z first
    const Eigen::Vector3d centre(x, y, z);
    pose.translation() = centre - pose.linear() * board.centre_mm();
    std::snprintf(name, sizeof name, "b_shared%02d", v);
    plan.push_back({name, pose});
  }
  // The board laid on the floor: at the origin, then on a circle of 1 m around it, turned any way
  // (one board moved from spot to spot).
  const auto floor_names = floor_view_names(options);
  for (size_t k = 0; k < floor_names.size(); ++k) {
    Eigen::Isometry3d pose = floor_board_pose(board);
    if (k > 0) {
      const double a =
          2 * M_PI * static_cast<double>(k - 1) / static_cast<double>(floor_names.size() - 1) +
          0.3 * u(rng);
      pose.prerotate(Eigen::AngleAxisd(M_PI * u(rng), Eigen::Vector3d::UnitZ()));
      pose.pretranslate(Eigen::Vector3d(1000 * std::cos(a), 1000 * std::sin(a), 0));
    }
    plan.push_back({floor_names[k], pose});
  }
  return plan;
}

std::vector<cv::Point2f> project_board(const CameraModel& c, const BoardSpec& board,
                                       const Eigen::Isometry3d& world_from_board, double noise_px,
                                       std::mt19937& rng) {
  if (!seen_head_on_enough(board, cam_pose(c) * world_from_board) ||
      !board_inside(c, board, world_from_board, 2))
    return {};
  std::normal_distribution<double> noise(0, noise_px);
  std::vector<cv::Point2f> corners;
  for (int k = 0; k < board.corner_count(); ++k) {
    const Eigen::Vector2d p = *c.project(world_from_board * board.corner_mm(k));
    const double ny = noise(rng), nx = noise(rng);  // y first: see make_ring_rig
    corners.emplace_back(static_cast<float>(p.x() + nx), static_cast<float>(p.y() + ny));
  }
  return corners;
}

BoardRenderer::BoardRenderer(const Rig& rig, BoardSpec board, double corner_noise_px,
                             double pixel_noise)
    : rig_(rig), board_(board), corner_noise_px_(corner_noise_px), pixel_noise_(pixel_noise) {
  // The exact (iterative) undistortion on a 4 px lattice, bilinear in between: the map is smooth
  // enough that this is exact to a few thousandths of a pixel, and 16 times cheaper.
  constexpr int kStep = 4;
  for (const auto& c : rig.cameras) {
    const int gw = c.width / kStep + 2, gh = c.height / kStep + 2;
    std::vector<Eigen::Vector2d> grid(static_cast<size_t>(gw * gh));
    for (int gy = 0; gy < gh; ++gy)
      for (int gx = 0; gx < gw; ++gx)
        grid[static_cast<size_t>(gy * gw + gx)] = c.undistort_pixel({gx * kStep, gy * kStep});
    cv::Mat map(c.height, c.width, CV_64FC2);
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        const int gx = x / kStep, gy = y / kStep;
        const double a = static_cast<double>(x % kStep) / kStep,
                     b = static_cast<double>(y % kStep) / kStep;
        auto g = [&](int i, int j) { return grid[static_cast<size_t>((gy + j) * gw + gx + i)]; };
        const Eigen::Vector2d n = (1 - a) * (1 - b) * g(0, 0) + a * (1 - b) * g(1, 0) +
                                  (1 - a) * b * g(0, 1) + a * b * g(1, 1);
        map.at<cv::Vec2d>(y, x) = {n.x(), n.y()};
      }
    normalised_.push_back(map);
  }
}

cv::Mat BoardRenderer::render(size_t index, const Eigen::Isometry3d& world_from_board,
                              std::mt19937& rng) const {
  const CameraModel& c = rig_.cameras[index];
  const Eigen::Isometry3d cam_from_board = cam_pose(c) * world_from_board;
  // A board seen from behind, beyond the detector's reach or partly outside the image carries
  // nothing the calibration could use and detecting it only costs test time: such a camera
  // delivers no image.
  if (!seen_head_on_enough(board_, cam_from_board) || !board_inside(c, board_, world_from_board, 2))
    return {};

  // Plane homography: normalised image point ~ M * (X, Y, 1) for board point (X, Y, 0) in mm.
  Eigen::Matrix3d M;
  M.col(0) = cam_from_board.linear().col(0);
  M.col(1) = cam_from_board.linear().col(1);
  M.col(2) = cam_from_board.translation();
  const Eigen::Matrix3d Minv = M.inverse();

  // Corner displacements: N(0, sigma^2) px in the image, mapped to board units (squares)
  // through the local Jacobian of the projection; interpolated bilinearly in between.
  const int cols = board_.cols, rows = board_.rows;
  std::normal_distribution<double> noise(0, corner_noise_px_);
  std::vector<Eigen::Vector2d> disp(static_cast<size_t>(cols * rows));
  for (int k = 0; k < cols * rows; ++k) {
    const Eigen::Vector3d p = world_from_board * board_.corner_mm(k);
    const double h = 1.0;  // mm
    const auto p0 = c.project(p);
    const auto px = c.project(p + world_from_board.linear() * Eigen::Vector3d(h, 0, 0));
    const auto py = c.project(p + world_from_board.linear() * Eigen::Vector3d(0, h, 0));
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    if (p0 && px && py) {
      Eigen::Matrix2d J;  // pixels per square
      J.col(0) = (*px - *p0) / h * board_.square_mm;
      J.col(1) = (*py - *p0) / h * board_.square_mm;
      const double ny = noise(rng), nx = noise(rng);  // y first: see make_ring_rig
      d = J.inverse() * Eigen::Vector2d(nx, ny);
    }
    disp[static_cast<size_t>(k)] = d;
  }
  auto displacement = [&](double u, double v) -> Eigen::Vector2d {
    u = std::clamp(u, 0.0, cols - 1.0);
    v = std::clamp(v, 0.0, rows - 1.0);
    const int i = std::min(static_cast<int>(u), cols - 2),
              j = std::min(static_cast<int>(v), rows - 2);
    const double a = u - i, b = v - j;
    auto at = [&](int ii, int jj) { return disp[static_cast<size_t>(jj * cols + ii)]; };
    return (1 - a) * (1 - b) * at(i, j) + a * (1 - b) * at(i + 1, j) + (1 - a) * b * at(i, j + 1) +
           a * b * at(i + 1, j + 1);
  };
  // Paper: squares from -1 to cols (rows) in corner units, plus half a square of white margin.
  constexpr double kBlack = 25, kWhite = 230, kBackground = 110;
  auto shade = [&](double u, double v) {
    if (u < -1.5 || v < -1.5 || u > cols + 0.5 || v > rows + 0.5) return kBackground;
    const Eigen::Vector2d q = Eigen::Vector2d(u, v) - displacement(u, v);
    if (q.x() < -1 || q.y() < -1 || q.x() > cols || q.y() > rows) return kWhite;
    const long parity = static_cast<long>(std::floor(q.x())) + static_cast<long>(std::floor(q.y()));
    return (parity & 1) ? kWhite : kBlack;
  };

  // Only pixels near the projected paper need the supersampled evaluation.
  int x0 = 0, y0 = 0, x1 = c.width - 1, y1 = c.height - 1;
  {
    double bx0 = 1e9, by0 = 1e9, bx1 = -1e9, by1 = -1e9;
    bool all_front = true;
    for (int s = 0; s <= 40 && all_front; ++s) {
      const double f = s / 40.0;
      const double U[4] = {-1.5 + f * (cols + 2), cols + 0.5, cols + 0.5 - f * (cols + 2), -1.5};
      const double V[4] = {-1.5, -1.5 + f * (rows + 2), rows + 0.5, rows + 0.5 - f * (rows + 2)};
      for (int e = 0; e < 4; ++e) {
        const auto p = c.project(world_from_board * Eigen::Vector3d(U[e] * board_.square_mm,
                                                                    V[e] * board_.square_mm, 0));
        if (!p) {
          all_front = false;
          break;
        }
        bx0 = std::min(bx0, p->x());
        by0 = std::min(by0, p->y());
        bx1 = std::max(bx1, p->x());
        by1 = std::max(by1, p->y());
      }
    }
    if (all_front) {
      x0 = std::max(0, static_cast<int>(bx0) - 3);
      y0 = std::max(0, static_cast<int>(by0) - 3);
      x1 = std::min(c.width - 1, static_cast<int>(bx1) + 3);
      y1 = std::min(c.height - 1, static_cast<int>(by1) + 3);
    }
  }
  cv::Mat shade_sum(c.height, c.width, CV_64F, cv::Scalar(kBackground));
  const cv::Mat& map = normalised_[index];
  constexpr int kSub = 4;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      // Sub-sample positions from the pixel centre's normalised coordinates and the local
      // derivatives of the (smooth) undistortion map.
      const cv::Vec2d n = map.at<cv::Vec2d>(y, x);
      const cv::Vec2d dx = (map.at<cv::Vec2d>(y, std::min(x + 1, c.width - 1)) -
                            map.at<cv::Vec2d>(y, std::max(x - 1, 0))) /
                           (std::min(x + 1, c.width - 1) - std::max(x - 1, 0));
      const cv::Vec2d dy = (map.at<cv::Vec2d>(std::min(y + 1, c.height - 1), x) -
                            map.at<cv::Vec2d>(std::max(y - 1, 0), x)) /
                           (std::min(y + 1, c.height - 1) - std::max(y - 1, 0));
      double sum = 0;
      for (int sy = 0; sy < kSub; ++sy)
        for (int sx = 0; sx < kSub; ++sx) {
          const double ox = (sx + 0.5) / kSub - 0.5, oy = (sy + 0.5) / kSub - 0.5;
          const cv::Vec2d s = n + ox * dx + oy * dy;
          const Eigen::Vector3d b = Minv * Eigen::Vector3d(s[0], s[1], 1);
          if (b.z() <= 0) {
            sum += kBackground;
            continue;
          }
          sum += shade(b.x() / b.z() / board_.square_mm, b.y() / b.z() / board_.square_mm);
        }
      shade_sum.at<double>(y, x) = sum / (kSub * kSub);
    }
  cv::Mat noise_img(c.height, c.width, CV_64F);
  cv::RNG cvrng(rng());
  cvrng.fill(noise_img, cv::RNG::NORMAL, 0, pixel_noise_);
  cv::Mat out;
  cv::Mat(shade_sum + noise_img).convertTo(out, CV_8U);
  return out;
}

SyntheticViewProvider::SyntheticViewProvider(const Rig& rig, const BoardRenderer& renderer,
                                             std::vector<PlannedView> plan, unsigned seed)
    : rig_(rig), renderer_(renderer), plan_(std::move(plan)), rng_(seed) {}

bool SyntheticViewProvider::next(CaptureInstant& out) {
  if (cursor_ >= plan_.size()) return false;
  const auto& view = plan_[cursor_++];
  out.name = view.name;
  out.images.clear();
  for (size_t i = 0; i < rig_.cameras.size(); ++i) {
    cv::Mat image = renderer_.render(i, view.world_from_board, rng_);
    if (!image.empty()) out.images.push_back({rig_.cameras[i].id, std::move(image)});
  }
  return true;
}

}  // namespace hullpose::calibrate::testing

namespace hullpose::calibrate::testing {
namespace {

double angle_between_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() / kDeg;
}

CameraError camera_error(const CameraModel& t, const CameraModel& e) {
  return {t.id,        100 * (e.fx / t.fx - 1),          100 * (e.fy / t.fy - 1),    e.cx - t.cx,
          e.cy - t.cy, (e.centre() - t.centre()).norm(), angle_between_deg(e.R, t.R)};
}

}  // namespace

CameraError RigError::worst(bool relative_frame) const {
  CameraError w;
  w.id = -1;
  for (const auto& e : relative_frame ? relative : absolute) {
    w.fx_pct = std::max(w.fx_pct, std::abs(e.fx_pct));
    w.fy_pct = std::max(w.fy_pct, std::abs(e.fy_pct));
    w.cx_px = std::max(w.cx_px, std::abs(e.cx_px));
    w.cy_px = std::max(w.cy_px, std::abs(e.cy_px));
    w.centre_mm = std::max(w.centre_mm, e.centre_mm);
    w.angle_deg = std::max(w.angle_deg, e.angle_deg);
  }
  return w;
}

RigError compare_rigs(const Rig& truth, const Rig& calibrated) {
  HULLPOSE_ASSERT(truth.cameras.size() == calibrated.cameras.size() && !truth.cameras.empty());
  // Kabsch on the camera centres, with fixed-size matrices only.
  const auto n = static_cast<double>(truth.cameras.size());
  Eigen::Vector3d mean_from = Eigen::Vector3d::Zero(), mean_to = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    mean_from += calibrated.cameras[i].centre() / n;
    mean_to += truth.cameras[i].centre() / n;
  }
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < truth.cameras.size(); ++i)
    cov += (truth.cameras[i].centre() - mean_to) *
           (calibrated.cameras[i].centre() - mean_from).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d sign(1, 1, (svd.matrixU() * svd.matrixV().transpose()).determinant());
  RigError r;
  Eigen::Isometry3d& truth_from_calibrated = r.truth_from_calibrated;
  truth_from_calibrated.linear() = svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
  truth_from_calibrated.translation() = mean_to - truth_from_calibrated.linear() * mean_from;
  r.gauge_angle_deg = Eigen::AngleAxisd(truth_from_calibrated.linear()).angle() / kDeg;
  r.gauge_tilt_deg =
      std::acos(std::min(1.0, (truth_from_calibrated.linear() * Eigen::Vector3d::UnitZ()).z())) /
      kDeg;
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    const CameraModel& t = truth.cameras[i];
    HULLPOSE_ASSERT(t.id == calibrated.cameras[i].id);
    r.absolute.push_back(camera_error(t, calibrated.cameras[i]));
    // The calibrated camera moved into the truth's frame: cam_from_truth = cam_from_cal *
    // cal_from_truth.
    CameraModel moved = calibrated.cameras[i];
    const Eigen::Isometry3d calibrated_from_truth = truth_from_calibrated.inverse();
    moved.R = calibrated.cameras[i].R * calibrated_from_truth.linear();
    moved.t =
        calibrated.cameras[i].R * calibrated_from_truth.translation() + calibrated.cameras[i].t;
    r.relative.push_back(camera_error(t, moved));
    r.gauge_mean_shift_mm +=
        (calibrated_from_truth * t.centre() - t.centre()).norm() / static_cast<double>(n);
  }
  return r;
}

bool meets_issue_tolerances(const CameraError& e) {
  return std::abs(e.fx_pct) < 0.5 && std::abs(e.fy_pct) < 0.5 && std::abs(e.cx_px) < 2.0 &&
         std::abs(e.cy_px) < 2.0 && e.centre_mm < 5.0 && e.angle_deg < 0.2;
}

std::ostream& operator<<(std::ostream& out, const CameraError& e) {
  char line[200];
  std::snprintf(line, sizeof line,
                "fx %.3f %%, fy %.3f %%, cx %.3f px, cy %.3f px, centre %.3f mm, rotation %.3f deg",
                e.fx_pct, e.fy_pct, e.cx_px, e.cy_px, e.centre_mm, e.angle_deg);
  return out << (e.id >= 0 ? "cam" + std::to_string(e.id) : std::string("worst")) << ": " << line;
}

std::vector<Detection> render_and_detect(const Rig& rig, const BoardSpec& board,
                                         const std::vector<PlannedView>& plan,
                                         double corner_noise_px, unsigned seed) {
  const BoardRenderer renderer(rig, board, corner_noise_px / std::sqrt(2.0), 2.0);
  SyntheticViewProvider provider(rig, renderer, plan, seed);
  std::vector<Detection> detections;
  CaptureInstant instant;
  while (provider.next(instant)) {
    std::vector<std::vector<cv::Point2f>> corners(instant.images.size());
    cv::parallel_for_(cv::Range(0, static_cast<int>(instant.images.size())),
                      [&](const cv::Range& r) {
                        for (int i = r.start; i < r.end; ++i)
                          corners[static_cast<size_t>(i)] =
                              detect_board(instant.images[static_cast<size_t>(i)].image, board);
                      });
    for (size_t i = 0; i < instant.images.size(); ++i)
      detections.push_back({instant.name, instant.images[i].camera_id,
                            instant.images[i].image.size(), std::move(corners[i])});
  }
  return detections;
}

}  // namespace hullpose::calibrate::testing
