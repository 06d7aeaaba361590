#include "hullpose/calibrate/rig_compare.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <iomanip>
#include <ostream>

#include "hullpose/common/check.hpp"

namespace hullpose::calibrate {

RigDifference compare_rigs(const Rig& rig, const Rig& other) {
  std::vector<std::pair<const CameraModel*, const CameraModel*>> pairs;
  for (const CameraModel& c : rig.cameras)
    if (const CameraModel* o = other.find(c.id)) pairs.emplace_back(&c, o);
  HULLPOSE_THROW_UNLESS(pairs.size() >= 3, "--compare: the rigs have "
                                               << pairs.size()
                                               << " camera ids in common; need 3 or more");
  // Kabsch on fixed-size 3x3 sums (Eigen::umeyama's dynamic matrices trip GCC 12's
  // maybe-uninitialized warning in Eigen's AVX-512 packing code).
  Eigen::Vector3d mean_a = Eigen::Vector3d::Zero(), mean_b = Eigen::Vector3d::Zero();
  for (const auto& [a, b] : pairs) {
    mean_a += a->centre();
    mean_b += b->centre();
  }
  mean_a /= static_cast<double>(pairs.size());
  mean_b /= static_cast<double>(pairs.size());
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (const auto& [a, b] : pairs) H += (a->centre() - mean_a) * (b->centre() - mean_b).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  Eigen::Isometry3d other_from_this = Eigen::Isometry3d::Identity();
  other_from_this.linear() = svd.matrixV() * D * svd.matrixU().transpose();
  other_from_this.translation() = mean_b - other_from_this.linear() * mean_a;
  RigDifference d;
  d.frame_rotation_deg = Eigen::AngleAxisd(other_from_this.linear()).angle() * 180 / M_PI;
  d.frame_translation_mm = other_from_this.translation().norm();
  for (const auto& [a, b] : pairs) {
    CameraDifference c;
    c.id = a->id;
    c.centre_mm = (other_from_this * a->centre() - b->centre()).norm();
    // World -> camera of `a` expressed in the other's world: R_a * R_alignᵀ.
    const Eigen::Matrix3d aligned = a->R * other_from_this.linear().transpose();
    c.orientation_deg = Eigen::AngleAxisd(aligned * b->R.transpose()).angle() * 180 / M_PI;
    c.focal_pct = 50 * ((a->fx - b->fx) / b->fx + (a->fy - b->fy) / b->fy);
    c.principal_px = std::hypot(a->cx - b->cx, a->cy - b->cy);
    d.cameras.push_back(c);
  }
  return d;
}

void print_difference(std::ostream& out, const RigDifference& d) {
  out << std::fixed << std::setprecision(1) << "compared (world frames aligned by a turn of "
      << d.frame_rotation_deg << " deg and a shift of " << d.frame_translation_mm << " mm):\n"
      << "  camera  centre mm  orientation deg  focal %  principal px\n";
  for (const CameraDifference& c : d.cameras)
    out << "  " << std::setw(6) << c.id << std::setw(11) << std::setprecision(1) << c.centre_mm
        << std::setw(17) << std::setprecision(2) << c.orientation_deg << std::setw(9)
        << std::setprecision(2) << c.focal_pct << std::setw(14) << std::setprecision(1)
        << c.principal_px << "\n";
}

}  // namespace hullpose::calibrate
