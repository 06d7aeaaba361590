#include "hullpose/pose/geometry.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace hullpose::pose {

Line fit_line(const MomentAccumulator& m) {
  Line line;
  line.point = m.centroid();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(m.scatter());
  line.direction = es.eigenvectors().col(2).normalized();  // eigenvalues ascend
  return line;
}

Eigen::Vector3d fit_plane_normal(const MomentAccumulator& m) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(m.scatter());
  return es.eigenvectors().col(0).normalized();
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace hullpose::pose
