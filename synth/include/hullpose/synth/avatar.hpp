#pragma once
// The avatar: capsules and ellipsoids hung on the 25-joint skeleton, sized from the stature
// with anthropometric girths (an average adult of 1750 mm has e.g. a 560 mm thigh girth), a
// build factor from slim child to large adult, and optional loose-clothing bulges.
#include <Eigen/Core>
#include <cstdint>
#include <string_view>
#include <vector>

#include "hullpose/common/dataset.hpp"

namespace hullpose::synth {

enum class Material : uint8_t { Skin, Hair, Shirt, Trousers, Shoes };
inline constexpr int kNumMaterials = 5;

// A capsule (segment a-b swept by a sphere of radius r; a == b is a sphere) or an ellipsoid
// (centre a, semi-axes as the columns of `axes`).
struct Primitive {
  enum class Kind : uint8_t { Capsule, Ellipsoid } kind = Kind::Capsule;
  Material material = Material::Skin;
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double r = 0;
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();

  static Primitive capsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                           Material m);
  static Primitive sphere(const Eigen::Vector3d& c, double r, Material m) {
    return capsule(c, c, r, m);
  }
  static Primitive ellipsoid(const Eigen::Vector3d& c, const Eigen::Matrix3d& axes, Material m);
  // Centre and radius of a sphere that contains the primitive.
  Eigen::Vector3d bound_centre() const;
  double bound_radius() const;
};

struct BodyShape {
  double stature_mm = 1750;
  double build = 1.0;      // girth multiplier: about 0.85 (slim, child) .. 1.35 (large adult)
  double clothing_mm = 0;  // loose clothing: extra thickness on torso, upper arms and thighs

  // "slim" | "average" | "large" (build only; the stature comes from the motion).
  static double build_preset(std::string_view name);
  // How far the soles reach below the ankle, ball and toe joints (floor placement).
  double sole_radius_mm(Joint j) const;
};

// Rebuilds `out` (capacity kept) with the avatar in the pose `joints`.
void pose_avatar(const BodyShape& shape, const JointPositions& joints, std::vector<Primitive>& out);

}  // namespace hullpose::synth
