#include "hullpose/common/camera.hpp"

#include <Eigen/Geometry>

namespace hullpose {

Eigen::Matrix3d CameraModel::K() const {
  Eigen::Matrix3d k;
  k << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return k;
}

bool CameraModel::has_distortion() const {
  for (double d : dist)
    if (d != 0.0) return true;
  return false;
}

Eigen::Vector2d CameraModel::distort_normalised(const Eigen::Vector2d& xn) const {
  const double x = xn.x(), y = xn.y();
  const double r2 = x * x + y * y;
  const auto [k1, k2, p1, p2, k3] = dist;
  const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  return {fx * xd + cx, fy * yd + cy};
}

std::optional<Eigen::Vector2d> CameraModel::project(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d c = R * world + t;
  if (c.z() <= 0) return std::nullopt;
  return distort_normalised({c.x() / c.z(), c.y() / c.z()});
}

Eigen::Vector2d CameraModel::undistort_pixel(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d xd((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  if (!has_distortion()) return xd;
  // Fixed-point iteration as in cv::undistortPoints, then Gauss-Newton polish so that
  // distort_normalised(result) reproduces `pixel` to well below a micro-pixel.
  const auto [k1, k2, p1, p2, k3] = dist;
  Eigen::Vector2d x = xd;
  for (int i = 0; i < 20; ++i) {
    const double r2 = x.squaredNorm();
    const double icdist = 1 / (1 + r2 * (k1 + r2 * (k2 + r2 * k3)));
    const double dx = 2 * p1 * x.x() * x.y() + p2 * (r2 + 2 * x.x() * x.x());
    const double dy = p1 * (r2 + 2 * x.y() * x.y()) + 2 * p2 * x.x() * x.y();
    x = Eigen::Vector2d((xd.x() - dx) * icdist, (xd.y() - dy) * icdist);
  }
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d residual = distort_normalised(x) - pixel;
    constexpr double h = 1e-7;
    Eigen::Matrix2d J;
    J.col(0) = (distort_normalised(x + Eigen::Vector2d(h, 0)) - distort_normalised(x)) / h;
    J.col(1) = (distort_normalised(x + Eigen::Vector2d(0, h)) - distort_normalised(x)) / h;
    x -= J.partialPivLu().solve(residual);
  }
  return x;
}

Eigen::Vector3d CameraModel::back_project(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d xn = undistort_pixel(pixel);
  return (R.transpose() * Eigen::Vector3d(xn.x(), xn.y(), 1.0)).normalized();
}

Eigen::Vector3d CameraModel::back_project(const Eigen::Vector2d& pixel, double depth_mm) const {
  const Eigen::Vector2d xn = undistort_pixel(pixel);
  const Eigen::Vector3d cam(xn.x() * depth_mm, xn.y() * depth_mm, depth_mm);
  return R.transpose() * (cam - t);
}

}  // namespace hullpose
