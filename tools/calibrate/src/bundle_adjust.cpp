// GCC 12 with -march=native reports false "uninitialized" warnings inside Eigen's AVX-512
// dense kernels (_mm512_undefined_pd used as a blend operand); they are not ours to fix.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
#include "hullpose/calibrate/bundle_adjust.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose::calibrate {

HULLPOSE_LOG_DECLARE_CATEGORY(Calibrate)

namespace {

using CameraVector = Eigen::Matrix<double, kCameraParams, 1>;
using CameraBlock = Eigen::Matrix<double, kCameraParams, kCameraParams>;
using BoardVector = Eigen::Matrix<double, 6, 1>;
using BoardBlock = Eigen::Matrix<double, 6, 6>;
using Coupling = Eigen::Matrix<double, kCameraParams, 6>;

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d rotation_step(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

// Sum of squared residuals; infinity if a point falls behind a camera.
double total_cost(const BundleProblem& p, const std::vector<CameraModel>& cameras,
                  const std::vector<Eigen::Isometry3d>& boards) {
  double cost = 0;
  Eigen::Vector2d px;
  for (const auto& obs : p.observations) {
    const auto& cam = cameras[static_cast<size_t>(obs.camera)];
    const auto& board = boards[static_cast<size_t>(obs.board)];
    for (size_t j = 0; j < obs.pixels.size(); ++j) {
      if (!project_with_jacobians(cam, board, p.board_points[j], px, nullptr, nullptr))
        return std::numeric_limits<double>::infinity();
      cost += (px - obs.pixels[j]).squaredNorm();
    }
  }
  return cost;
}

size_t corner_total(const BundleProblem& p) {
  size_t n = 0;
  for (const auto& obs : p.observations) n += obs.pixels.size();
  return n;
}

}  // namespace

bool project_with_jacobians(const CameraModel& c, const Eigen::Isometry3d& world_from_board,
                            const Eigen::Vector3d& X, Eigen::Vector2d& pixel, CameraJacobian* jc,
                            BoardJacobian* jb) {
  const Eigen::Vector3d rbx = world_from_board.linear() * X;
  const Eigen::Vector3d pw = rbx + world_from_board.translation();
  const Eigen::Vector3d rcp = c.R * pw;
  const Eigen::Vector3d pc = rcp + c.t;
  if (pc.z() <= 1e-9) return false;
  const double iz = 1.0 / pc.z();
  const double x = pc.x() * iz, y = pc.y() * iz;
  const auto [k1, k2, p1, p2, k3] = c.dist;
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  pixel = {c.fx * xd + c.cx, c.fy * yd + c.cy};
  if (!jc && !jb) return true;

  // d radial / d r2, then the 2x2 Jacobian of the distorted point w.r.t. (x, y).
  const double drad = k1 + r2 * (2 * k2 + 3 * k3 * r2);
  Eigen::Matrix2d dd;
  dd(0, 0) = radial + 2 * x * x * drad + 2 * p1 * y + 6 * p2 * x;
  dd(0, 1) = 2 * x * y * drad + 2 * p1 * x + 2 * p2 * y;
  dd(1, 0) = 2 * x * y * drad + 2 * p1 * x + 2 * p2 * y;
  dd(1, 1) = radial + 2 * y * y * drad + 6 * p1 * y + 2 * p2 * x;
  Eigen::Matrix<double, 2, 3> dn;  // normalised point w.r.t. the camera-frame point
  dn << iz, 0, -x * iz, 0, iz, -y * iz;
  const Eigen::Matrix<double, 2, 3> dpix_dpc =
      Eigen::DiagonalMatrix<double, 2>(c.fx, c.fy) * dd * dn;

  if (jc) {
    jc->block<2, 3>(0, 0) = -dpix_dpc * skew(rcp);
    jc->block<2, 3>(0, 3) = dpix_dpc;
    jc->col(6) << xd, 0;
    jc->col(7) << 0, yd;
    jc->col(8) << 1, 0;
    jc->col(9) << 0, 1;
    jc->col(10) << c.fx * x * r2, c.fy * y * r2;
    jc->col(11) << c.fx * x * r2 * r2, c.fy * y * r2 * r2;
    jc->col(12) << c.fx * 2 * x * y, c.fy * (r2 + 2 * y * y);
    jc->col(13) << c.fx * (r2 + 2 * x * x), c.fy * 2 * x * y;
    jc->col(14) << c.fx * x * r2 * r2 * r2, c.fy * y * r2 * r2 * r2;
  }
  if (jb) {
    const Eigen::Matrix<double, 2, 3> dpix_dpw = dpix_dpc * c.R;
    jb->block<2, 3>(0, 0) = -dpix_dpw * skew(rbx);
    jb->block<2, 3>(0, 3) = dpix_dpw;
  }
  return true;
}

void apply_camera_step(CameraModel& c, const CameraVector& s) {
  c.R = rotation_step(s.segment<3>(0)) * c.R;
  c.t += s.segment<3>(3);
  c.fx += s(6);
  c.fy += s(7);
  c.cx += s(8);
  c.cy += s(9);
  c.dist[0] += s(10);
  c.dist[1] += s(11);
  c.dist[2] += s(12);
  c.dist[3] += s(13);
  c.dist[4] += s(14);
}

void apply_board_step(Eigen::Isometry3d& b, const BoardVector& s) {
  b.linear() = rotation_step(s.segment<3>(0)) * b.linear();
  b.translation() += s.segment<3>(3);
}

BundleResult bundle_adjust(BundleProblem& p, const BundleOptions& options) {
  const size_t n_cams = p.cameras.size();
  const size_t n_boards = p.world_from_board.size();
  HULLPOSE_ASSERT(p.board_motion.size() == n_boards);
  HULLPOSE_THROW_UNLESS(std::find(p.board_motion.begin(), p.board_motion.end(),
                                  BoardMotion::kFixed) != p.board_motion.end(),
                        "bundle adjustment: no board is fixed, the world frame is free");
  for (const auto& obs : p.observations)
    HULLPOSE_ASSERT(obs.pixels.size() == p.board_points.size() && obs.camera >= 0 &&
                    static_cast<size_t>(obs.camera) < n_cams && obs.board >= 0 &&
                    static_cast<size_t>(obs.board) < n_boards);

  // Parameters held constant get a zero Jacobian column and a unit diagonal, so their step is 0.
  std::array<bool, kCameraParams> free{};
  for (int i = 0; i < kCameraParams; ++i)
    free[static_cast<size_t>(i)] = i < 6 || options.refine_intrinsics;
  if (!options.refine_k3) free[14] = false;
  // A board on the floor turns about world z (rotation increments are in the world frame) and
  // slides in x and y; a fixed board has no parameters at all (its blocks are skipped).
  std::vector<std::array<bool, 6>> board_free(n_boards);
  for (size_t b = 0; b < n_boards; ++b)
    board_free[b] = p.board_motion[b] == BoardMotion::kOnFloor
                        ? std::array<bool, 6>{false, false, true, true, true, false}
                        : std::array<bool, 6>{true, true, true, true, true, true};

  // Observations grouped by board, for the Schur complement.
  std::vector<std::vector<size_t>> by_board(n_boards);
  for (size_t o = 0; o < p.observations.size(); ++o)
    by_board[static_cast<size_t>(p.observations[o].board)].push_back(o);
  auto moves = [&](size_t b) {
    return p.board_motion[b] != BoardMotion::kFixed && !by_board[b].empty();
  };

  const size_t n_corners = corner_total(p);
  HULLPOSE_ASSERT(n_corners > 0);
  double cost = total_cost(p, p.cameras, p.world_from_board);
  HULLPOSE_THROW_UNLESS(
      std::isfinite(cost),
      "bundle adjustment: a board corner lies behind a camera in the initial rig; "
      "the cameras were linked inconsistently");
  BundleResult result;
  result.initial_rms_px = std::sqrt(cost / static_cast<double>(n_corners));

  std::vector<CameraBlock> U(n_cams);
  std::vector<CameraVector> gc(n_cams);
  std::vector<BoardBlock> V(n_boards);
  std::vector<BoardVector> gb(n_boards);
  std::vector<Coupling> W(p.observations.size());
  const Eigen::Index dim = static_cast<Eigen::Index>(n_cams) * kCameraParams;
  double lambda = 1e-3;
  CameraJacobian jc;
  BoardJacobian jb;
  Eigen::Vector2d px;

  int iter = 0;
  bool converged = false;
  for (; iter < options.max_iterations && !converged; ++iter) {
    for (auto& m : U) m.setZero();
    for (auto& v : gc) v.setZero();
    for (auto& m : V) m.setZero();
    for (auto& v : gb) v.setZero();
    for (size_t o = 0; o < p.observations.size(); ++o) {
      const auto& obs = p.observations[o];
      const auto c = static_cast<size_t>(obs.camera), b = static_cast<size_t>(obs.board);
      W[o].setZero();
      for (size_t j = 0; j < obs.pixels.size(); ++j) {
        const bool ok = project_with_jacobians(p.cameras[c], p.world_from_board[b],
                                               p.board_points[j], px, &jc, &jb);
        HULLPOSE_ASSERT(ok);  // the cost is finite, so every point is in front
        for (int i = 0; i < kCameraParams; ++i)
          if (!free[static_cast<size_t>(i)]) jc.col(i).setZero();
        for (int i = 0; i < 6; ++i)
          if (!board_free[b][static_cast<size_t>(i)]) jb.col(i).setZero();
        const Eigen::Vector2d r = px - obs.pixels[j];
        U[c].noalias() += jc.transpose() * jc;
        gc[c].noalias() += jc.transpose() * r;
        if (moves(b)) {
          V[b].noalias() += jb.transpose() * jb;
          gb[b].noalias() += jb.transpose() * r;
          W[o].noalias() += jc.transpose() * jb;
        }
      }
    }

    bool accepted = false;
    while (!accepted && lambda < 1e12) {
      // Marquardt damping, then the Schur complement S dc = rhs over the camera blocks.
      Eigen::MatrixXd S = Eigen::MatrixXd::Zero(dim, dim);
      Eigen::VectorXd rhs(dim);
      for (size_t c = 0; c < n_cams; ++c) {
        CameraBlock a = U[c];
        for (int i = 0; i < kCameraParams; ++i)
          a(i, i) = free[static_cast<size_t>(i)] ? a(i, i) * (1 + lambda) + 1e-12 : 1.0;
        S.block<kCameraParams, kCameraParams>(static_cast<Eigen::Index>(c) * kCameraParams,
                                              static_cast<Eigen::Index>(c) * kCameraParams) = a;
        rhs.segment<kCameraParams>(static_cast<Eigen::Index>(c) * kCameraParams) = -gc[c];
      }
      std::vector<BoardBlock> Vinv(n_boards);
      for (size_t b = 0; b < n_boards; ++b) {
        if (!moves(b)) continue;
        BoardBlock a = V[b];
        for (int i = 0; i < 6; ++i)
          a(i, i) = board_free[b][static_cast<size_t>(i)] ? a(i, i) * (1 + lambda) + 1e-12 : 1.0;
        Vinv[b] = a.ldlt().solve(BoardBlock::Identity());
        for (size_t o1 : by_board[b]) {
          const auto c1 = static_cast<Eigen::Index>(p.observations[o1].camera);
          const Coupling wv = W[o1] * Vinv[b];
          rhs.segment<kCameraParams>(c1 * kCameraParams) += wv * gb[b];
          for (size_t o2 : by_board[b]) {
            const auto c2 = static_cast<Eigen::Index>(p.observations[o2].camera);
            S.block<kCameraParams, kCameraParams>(c1 * kCameraParams, c2 * kCameraParams) -=
                wv * W[o2].transpose();
          }
        }
      }
      const Eigen::VectorXd dc = S.llt().solve(rhs);
      if (!dc.allFinite()) {
        lambda *= 10;
        continue;
      }
      std::vector<CameraModel> trial_cameras = p.cameras;
      std::vector<Eigen::Isometry3d> trial_boards = p.world_from_board;
      double step_norm = 0;
      for (size_t c = 0; c < n_cams; ++c) {
        const CameraVector step =
            dc.segment<kCameraParams>(static_cast<Eigen::Index>(c) * kCameraParams);
        step_norm += step.squaredNorm();
        apply_camera_step(trial_cameras[c], step);
      }
      for (size_t b = 0; b < n_boards; ++b) {
        if (!moves(b)) continue;
        BoardVector rb = -gb[b];
        for (size_t o : by_board[b])
          rb -= W[o].transpose() *
                dc.segment<kCameraParams>(static_cast<Eigen::Index>(p.observations[o].camera) *
                                          kCameraParams);
        const BoardVector db = Vinv[b] * rb;
        step_norm += db.squaredNorm();
        apply_board_step(trial_boards[b], db);
      }
      const double trial_cost = total_cost(p, trial_cameras, trial_boards);
      if (trial_cost < cost) {
        const double gain = (cost - trial_cost) / cost;
        p.cameras = std::move(trial_cameras);
        p.world_from_board = std::move(trial_boards);
        cost = trial_cost;
        lambda = std::max(lambda / 10, 1e-12);
        accepted = true;
        HULLPOSE_LOG(Calibrate, Debug) << "bundle adjustment iteration " << iter << ": rms "
                                       << std::sqrt(cost / static_cast<double>(n_corners)) << " px";
        converged = gain < 1e-12 || step_norm < 1e-20;
      } else {
        lambda *= 10;
      }
    }
    if (!accepted) converged = true;  // no step improves the cost any more
  }
  result.iterations = iter;
  result.final_rms_px = std::sqrt(cost / static_cast<double>(n_corners));
  std::vector<double> sum(n_cams, 0.0);
  result.camera_corners.assign(n_cams, 0);
  for (const auto& obs : p.observations) {
    const auto c = static_cast<size_t>(obs.camera);
    for (size_t j = 0; j < obs.pixels.size(); ++j) {
      project_with_jacobians(p.cameras[c], p.world_from_board[static_cast<size_t>(obs.board)],
                             p.board_points[j], px, nullptr, nullptr);
      sum[c] += (px - obs.pixels[j]).squaredNorm();
      ++result.camera_corners[c];
    }
  }
  result.camera_rms_px.resize(n_cams);
  for (size_t c = 0; c < n_cams; ++c)
    result.camera_rms_px[c] =
        result.camera_corners[c] ? std::sqrt(sum[c] / result.camera_corners[c]) : 0.0;
  return result;
}

}  // namespace hullpose::calibrate
