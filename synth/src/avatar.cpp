#include "hullpose/synth/avatar.hpp"

#include <Eigen/Geometry>
#include <algorithm>

#include "hullpose/common/check.hpp"

namespace hullpose::synth {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Radii as fractions of stature, from girths of an average adult of 1750 mm (girth / 2 pi):
// neck 380 mm, upper arm 300, forearm 250, thigh 560, calf 370; chest breadth 330, depth 225;
// waist breadth 280, depth 200; hip breadth 345, depth 220; head 230 x 156 x 192.
constexpr double kNeck = 0.031, kShoulder = 0.029, kUpperArm = 0.027, kForearm = 0.022,
                 kHand = 0.016;
constexpr double kThigh = 0.046, kCalf = 0.032, kFoot = 0.022, kToe = 0.014;

// Orthonormal frame with `up` exact and `lateral` (left) made orthogonal to it.
Matrix3d frame(const Vector3d& up_in, const Vector3d& lateral_in) {
  const Vector3d up = up_in.normalized();
  Vector3d lat = lateral_in - lateral_in.dot(up) * up;
  if (lat.norm() < 1e-9) lat = up.unitOrthogonal();
  lat.normalize();
  Matrix3d f;
  f.col(0) = lat.cross(up);  // forward
  f.col(1) = lat;
  f.col(2) = up;
  return f;
}

Matrix3d semi_axes(const Matrix3d& f, double forward, double lateral, double up) {
  Matrix3d a;
  a.col(0) = f.col(0) * forward;
  a.col(1) = f.col(1) * lateral;
  a.col(2) = f.col(2) * up;
  return a;
}

}  // namespace

Primitive Primitive::capsule(const Vector3d& a, const Vector3d& b, double r, Material m) {
  Primitive p;
  p.kind = Kind::Capsule;
  p.material = m;
  p.a = a;
  p.b = b;
  p.r = r;
  return p;
}

Primitive Primitive::ellipsoid(const Vector3d& c, const Matrix3d& axes, Material m) {
  Primitive p;
  p.kind = Kind::Ellipsoid;
  p.material = m;
  p.a = c;
  p.b = c;
  p.axes = axes;
  p.r = axes.colwise().norm().maxCoeff();
  return p;
}

Vector3d Primitive::bound_centre() const {
  return 0.5 * (a + b);
}
double Primitive::bound_radius() const {
  return 0.5 * (b - a).norm() + r;
}

double BodyShape::build_preset(std::string_view name) {
  if (name == "slim") return 0.85;
  if (name == "average") return 1.0;
  if (name == "large") return 1.35;
  HULLPOSE_THROW("unknown body build '" << name << "' (slim, average, large)");
}

double BodyShape::sole_radius_mm(Joint j) const {
  const double s = stature_mm * build;
  switch (j) {
    case Joint::LAnk:
    case Joint::RAnk:
    case Joint::LFoot:
    case Joint::RFoot:
      return kFoot * s;
    case Joint::LToe:
    case Joint::RToe:
      return kToe * s;
    default:
      return 0;
  }
}

void pose_avatar(const BodyShape& shape, const JointPositions& p, std::vector<Primitive>& out) {
  out.clear();
  auto at = [&](Joint j) -> const Vector3d& { return p[static_cast<size_t>(index(j))]; };
  const double s = shape.stature_mm, g = s * shape.build, cloth = shape.clothing_mm;
  using M = Material;

  // Head: ellipsoid whose crown is HeadTop (so the silhouette's top is the stature).
  const Vector3d lateral = at(Joint::LSho) - at(Joint::RSho);
  const Matrix3d fh = frame(at(Joint::HeadTop) - at(Joint::Head), lateral);
  const double head_up = 0.066 * s;
  out.push_back(Primitive::ellipsoid(at(Joint::HeadTop) - fh.col(2) * head_up,
                                     semi_axes(fh, 0.055 * s, 0.045 * s, head_up), M::Hair));
  out.push_back(Primitive::capsule(at(Joint::Chest), at(Joint::Head), kNeck * g, M::Skin));

  // Torso: chest, waist and pelvis ellipsoids along the spine.
  const Matrix3d fc = frame(at(Joint::Chest) - at(Joint::UBack), lateral);
  const double chest_h = 0.5 * (at(Joint::Chest) - at(Joint::Back)).norm();
  out.push_back(Primitive::ellipsoid(
      0.5 * (at(Joint::Chest) + at(Joint::Back)) - fc.col(2) * 0.01 * s,
      semi_axes(fc, 0.064 * g + cloth, 0.094 * g + cloth, chest_h * 1.15 + cloth), M::Shirt));
  const Vector3d hips = at(Joint::LHip) - at(Joint::RHip);
  const Matrix3d fw = frame(at(Joint::UBack) - at(Joint::LBack), hips);
  out.push_back(Primitive::ellipsoid(
      at(Joint::Back), semi_axes(fw, 0.057 * g + cloth, 0.08 * g + cloth, 0.075 * s + cloth),
      M::Shirt));
  const Matrix3d fp = frame(at(Joint::Back) - at(Joint::LBack), hips);
  out.push_back(Primitive::ellipsoid(
      at(Joint::LBack) - fp.col(2) * 0.025 * s,
      semi_axes(fp, 0.063 * g + 0.5 * cloth, 0.098 * g + 0.5 * cloth, 0.065 * s), M::Trousers));
  out.push_back(
      Primitive::capsule(at(Joint::LSho), at(Joint::RSho), kShoulder * g + cloth, M::Shirt));

  for (int side = 0; side < 2; ++side) {
    const bool l = side == 0;
    const Vector3d &sho = at(l ? Joint::LSho : Joint::RSho),
                   &elb = at(l ? Joint::LElb : Joint::RElb),
                   &hand = at(l ? Joint::LHand : Joint::RHand),
                   &tip = at(l ? Joint::LFTip : Joint::RFTip);
    out.push_back(Primitive::capsule(sho, elb, kUpperArm * g + 0.6 * cloth, M::Shirt));
    out.push_back(Primitive::capsule(elb, hand, kForearm * g, M::Skin));
    out.push_back(Primitive::capsule(hand, tip, kHand * g, M::Skin));
    const Vector3d &hip = at(l ? Joint::LHip : Joint::RHip),
                   &kne = at(l ? Joint::LKne : Joint::RKne),
                   &ank = at(l ? Joint::LAnk : Joint::RAnk),
                   &ball = at(l ? Joint::LFoot : Joint::RFoot),
                   &toe = at(l ? Joint::LToe : Joint::RToe);
    out.push_back(Primitive::capsule(hip, kne, kThigh * g + 0.6 * cloth, M::Trousers));
    out.push_back(Primitive::capsule(kne, ank, kCalf * g + 0.3 * cloth, M::Trousers));
    out.push_back(Primitive::capsule(ank, ball, kFoot * g, M::Shoes));
    out.push_back(Primitive::capsule(ball, toe, kToe * g, M::Shoes));
  }
}

}  // namespace hullpose::synth
