#pragma once
// Pinhole camera with OpenCV's 5-coefficient distortion (k1 k2 p1 p2 k3).
// Extrinsics map world to camera: X_cam = R * X_world + t. World units are millimetres,
// z up, floor at z = 0 (docs/conventions.md). Camera frame: x right, y down, z forward.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>

namespace hullpose {

struct CameraModel {
  int id = 0;
  std::string name;
  int width = 0;   // pixels
  int height = 0;  // pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 5> dist{};  // k1 k2 p1 p2 k3
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Matrix3d K() const;
  // Camera centre in world coordinates (mm).
  Eigen::Vector3d centre() const { return -R.transpose() * t; }
  bool has_distortion() const;

  // World point (mm) to pixel, distortion applied. std::nullopt if the point is not in front
  // of the camera (z_cam <= 0). Same model as cv::projectPoints.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& world) const;
  // Normalised undistorted image coordinates (x/z, y/z) to distorted pixel.
  Eigen::Vector2d distort_normalised(const Eigen::Vector2d& xn) const;
  // Pixel to normalised undistorted coordinates (iterative inverse of the distortion).
  Eigen::Vector2d undistort_pixel(const Eigen::Vector2d& pixel) const;
  // Pixel to the unit direction of its viewing ray, in world coordinates; the ray starts at
  // centre().
  Eigen::Vector3d back_project(const Eigen::Vector2d& pixel) const;
  // Pixel and depth along the camera's z axis (mm) to a world point.
  Eigen::Vector3d back_project(const Eigen::Vector2d& pixel, double depth_mm) const;
};

}  // namespace hullpose
