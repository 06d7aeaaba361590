#pragma once
// Small geometry the pose stages share: orthogonal-distance-regression (total least squares)
// lines and planes through node sets, with Eigen's closed-form 3x3 eigen solver (no allocation).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <span>

namespace hullpose::pose {

struct Line {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();       // centroid of the fitted points
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit
  Eigen::Vector3d project(const Eigen::Vector3d& p) const {
    return point + direction * direction.dot(p - point);
  }
  double distance(const Eigen::Vector3d& p) const { return (p - project(p)).norm(); }
};

// Accumulates points for an ODR fit without storing them.
class MomentAccumulator {
 public:
  void add(const Eigen::Vector3d& p) {
    ++n_;
    sum_ += p;
    outer_ += p * p.transpose();
  }
  int count() const { return n_; }
  Eigen::Vector3d centroid() const { return sum_ / n_; }
  // Scatter matrix about the centroid.
  Eigen::Matrix3d scatter() const {
    const Eigen::Vector3d c = centroid();
    return outer_ - n_ * c * c.transpose();
  }

 private:
  int n_ = 0;
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer_ = Eigen::Matrix3d::Zero();
};

// ODR line through >= 2 points: centroid and the principal axis of the scatter matrix.
Line fit_line(const MomentAccumulator& m);
// ODR plane normal (unit): the scatter matrix's least axis.
Eigen::Vector3d fit_plane_normal(const MomentAccumulator& m);
// Angle between two vectors in radians, 0..pi.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace hullpose::pose
