#include "hullpose/skeleton_io/bvh.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iomanip>

#include "hullpose/common/check.hpp"

namespace hullpose::skeleton_io {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = 180.0 / kPi;

int bone_index(int a, int b) {
  for (size_t i = 0; i < kBones.size(); ++i) {
    const int p = index(kBones[i].parent), c = index(kBones[i].child);
    if ((p == a && c == b) || (p == b && c == a)) return static_cast<int>(i);
  }
  return -1;
}

std::vector<int> neighbours(int j) {
  std::vector<int> out;
  for (const Bone& b : kBones) {
    if (index(b.parent) == j) out.push_back(index(b.child));
    if (index(b.child) == j) out.push_back(index(b.parent));
  }
  return out;
}

// T-pose rest direction of the bone from `from` to `to` (BVH frame: Y up, facing +Z, left +X).
Eigen::Vector3d rest_direction(int from, int to) {
  using J = Joint;
  const auto is = [&](J j) { return to == index(j); };
  if (is(J::LHip) || is(J::LSho) || is(J::LElb) || is(J::LHand) || is(J::LFTip))
    return Eigen::Vector3d::UnitX();
  if (is(J::RHip) || is(J::RSho) || is(J::RElb) || is(J::RHand) || is(J::RFTip))
    return -Eigen::Vector3d::UnitX();
  if (is(J::LKne) || is(J::RKne) || is(J::LAnk) || is(J::RAnk)) return -Eigen::Vector3d::UnitY();
  if (is(J::LFoot) || is(J::RFoot) || is(J::LToe) || is(J::RToe)) return Eigen::Vector3d::UnitZ();
  (void)from;
  return Eigen::Vector3d::UnitY();  // spine, neck, head
}

// Rotation taking unit-free vector a to b by the smallest angle (identity if either is ~0).
Eigen::Quaterniond swing(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (a.squaredNorm() < 1e-18 || b.squaredNorm() < 1e-18) return Eigen::Quaterniond::Identity();
  // Half-way quaternion (Eigen's FromTwoVectors takes an SVD for the opposite case, which
  // trips GCC 12's maybe-uninitialized in Eigen's AVX-512 kernels).
  const Eigen::Vector3d u = a.normalized(), v = b.normalized();
  const double w = 1 + u.dot(v);
  if (w < 1e-12) {
    const Eigen::Vector3d axis = u.unitOrthogonal();
    return Eigen::Quaterniond(0, axis.x(), axis.y(), axis.z());
  }
  const Eigen::Vector3d c = u.cross(v);
  return Eigen::Quaterniond(w, c.x(), c.y(), c.z()).normalized();
}

// R = Rz(z) Rx(x) Ry(y), angles in radians.
Eigen::Vector3d euler_zxy(const Eigen::Matrix3d& r) {
  const double x = std::asin(std::clamp(r(2, 1), -1.0, 1.0));
  if (std::abs(std::cos(x)) > 1e-9)
    return {std::atan2(-r(0, 1), r(1, 1)), x, std::atan2(-r(2, 0), r(2, 2))};
  return {std::atan2(r(1, 0), r(0, 0)), x, 0.0};
}

Eigen::Quaterniond from_euler_zxy_deg(double z, double x, double y) {
  return Eigen::AngleAxisd(z / kDeg, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(x / kDeg, Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(y / kDeg, Eigen::Vector3d::UnitY());
}

double unwrap(double angle_deg, double previous_deg) {
  return angle_deg + 360.0 * std::round((previous_deg - angle_deg) / 360.0);
}

}  // namespace

BoneLengths bone_lengths(const JointPositions& joints) {
  BoneLengths out{};
  for (size_t i = 0; i < kBones.size(); ++i)
    out[i] = (joints[static_cast<size_t>(index(kBones[i].child))] -
              joints[static_cast<size_t>(index(kBones[i].parent))])
                 .norm();
  return out;
}

int32_t held_model_version(const std::vector<SkeletonFrame>& frames) {
  int32_t newest = 0;
  for (const SkeletonFrame& f : frames)
    if (f.valid) newest = std::max(newest, f.model_version);
  return newest;
}

BoneLengths subject_bone_lengths(const std::vector<SkeletonFrame>& frames) {
  // The held model's frames agree to float rounding; their median also shrugs off a stray one.
  const int32_t model = held_model_version(frames);
  std::array<std::vector<double>, kNumBones> samples;
  for (const SkeletonFrame& f : frames) {
    if (!f.valid || (model > 0 && f.model_version != model)) continue;
    const BoneLengths l = bone_lengths(f.joints);
    for (size_t i = 0; i < kBones.size(); ++i) samples[i].push_back(l[i]);
  }
  HULLPOSE_THROW_UNLESS(!samples[0].empty(),
                        "no valid frame to take the subject's bone lengths from");
  BoneLengths out{};
  for (size_t i = 0; i < kBones.size(); ++i) {
    auto& v = samples[i];
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    out[i] = v[v.size() / 2];
  }
  return out;
}

Eigen::Vector3d BvhSkeleton::to_bvh(const Eigen::Vector3d& p) {
  return Eigen::Vector3d(p.x(), p.z(), -p.y()) / 10.0;
}
Eigen::Vector3d BvhSkeleton::from_bvh(const Eigen::Vector3d& p) {
  return Eigen::Vector3d(p.x(), -p.z(), p.y()) * 10.0;
}

int BvhSkeleton::add(std::string name, int parent, int joint, int child_joint,
                     const Eigen::Vector3d& offset, bool end_site) {
  nodes_.push_back({std::move(name), parent, joint, child_joint, offset, end_site});
  children_.emplace_back();
  const int id = static_cast<int>(nodes_.size()) - 1;
  if (parent >= 0) children_[static_cast<size_t>(parent)].push_back(id);
  if (!end_site) num_channels_ += parent < 0 ? 6 : 3;
  return id;
}

BvhSkeleton::BvhSkeleton(const BoneLengths& lengths) {
  for (size_t i = 0; i < lengths.size(); ++i)
    HULLPOSE_THROW_UNLESS(std::isfinite(lengths[i]) && lengths[i] > 0 && lengths[i] < 2000,
                          "bone " << i << " (" << kBones[i].name
                                  << "): length must be in (0, 2000) mm, got " << lengths[i]);
  const auto rest = [&](int from, int to) -> Eigen::Vector3d {
    return rest_direction(from, to) * lengths[static_cast<size_t>(bone_index(from, to))] / 10.0;
  };
  // Depth first from the pelvis, so nodes_ is in the order the hierarchy and the channels are
  // written.
  const auto build = [&](auto& self, int joint, int from, int parent,
                         const Eigen::Vector3d& offset) -> void {
    std::vector<int> next = neighbours(joint);
    next.erase(std::remove(next.begin(), next.end(), from), next.end());
    const auto attach = [&](int under, int child) {
      if (neighbours(child).size() == 1)
        add("End Site", under, child, -1, rest(joint, child), true);
      else
        self(self, child, joint, under, rest(joint, child));
    };
    if (next.size() == 1) {
      attach(add(std::string(kJointNames[static_cast<size_t>(joint)]), parent, joint, next[0],
                 offset, false),
             next[0]);
      return;
    }
    const int node =
        add(std::string(kJointNames[static_cast<size_t>(joint)]), parent, joint, -1, offset, false);
    for (int child : next) {
      const std::string name = std::string(kJointNames[static_cast<size_t>(joint)]) + "_" +
                               std::string(kJointNames[static_cast<size_t>(child)]);
      attach(add(name, node, joint, child, Eigen::Vector3d::Zero(), false), child);
    }
  };
  build(build, index(Joint::LBack), -1, -1, Eigen::Vector3d::Zero());
}

int BvhSkeleton::find(const std::string& name) const {
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].name == name) return static_cast<int>(i);
  return -1;
}

void BvhSkeleton::write_node(std::ostream& out, int id, int depth) const {
  const Node& n = nodes_[static_cast<size_t>(id)];
  const std::string pad(static_cast<size_t>(depth) * 2, ' ');
  out << pad << (n.end_site ? "End Site" : (n.parent < 0 ? "ROOT " : "JOINT ") + n.name) << "\n"
      << pad << "{\n";
  out << pad << "  OFFSET " << n.offset.x() << ' ' << n.offset.y() << ' ' << n.offset.z() << "\n";
  if (!n.end_site)
    out << pad
        << (n.parent < 0
                ? "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
                : "  CHANNELS 3 Zrotation Xrotation Yrotation\n");
  for (int c : children_[static_cast<size_t>(id)]) write_node(out, c, depth + 1);
  out << pad << "}\n";
}

void BvhSkeleton::write_hierarchy(std::ostream& out) const {
  const auto flags = out.flags();
  const auto precision = out.precision();
  out << std::fixed << std::setprecision(6) << "HIERARCHY\n";
  write_node(out, 0, 0);
  out.flags(flags);
  out.precision(precision);
}

void BvhSkeleton::write_header(std::ostream& out, int frames, double frame_time_s) const {
  write_hierarchy(out);
  const auto flags = out.flags();
  out << "MOTION\nFrames: " << frames << "\nFrame Time: " << std::fixed << std::setprecision(8)
      << frame_time_s << "\n";
  out.flags(flags);
}

void BvhSkeleton::solve_rotations(const JointPositions& joints_mm,
                                  std::vector<Eigen::Quaterniond>& global) const {
  global.resize(nodes_.size());
  const auto p = [&](int j) { return to_bvh(joints_mm[static_cast<size_t>(j)]); };
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    const Eigen::Quaterniond parent =
        n.parent < 0 ? Eigen::Quaterniond::Identity() : global[static_cast<size_t>(n.parent)];
    if (n.end_site) {
      global[i] = parent;
    } else if (n.child_joint >= 0) {
      // The one child's rest offset, turned the least (in the parent's frame) onto the bone.
      const Node& child = nodes_[static_cast<size_t>(children_[i].front())];
      global[i] =
          (parent * swing(child.offset, parent.conjugate() * (p(n.child_joint) - p(n.joint))))
              .normalized();
    } else {
      // The segment's frame from its children: up along the spine child (rest +Y), across from the
      // right child to the left one (rest +X), orthogonalised against up.
      Eigen::Vector3d up = Eigen::Vector3d::UnitY(), across = Eigen::Vector3d::UnitX();
      for (int d : children_[i]) {
        const int child = nodes_[static_cast<size_t>(d)].child_joint;
        const Eigen::Vector3d rest =
            nodes_[static_cast<size_t>(children_[static_cast<size_t>(d)].front())].offset;
        const Eigen::Vector3d seen = p(child) - p(n.joint);
        if (rest.y() > 0.5 * rest.norm())
          up = seen;
        else if (rest.x() > 0)
          across = across == Eigen::Vector3d::UnitX() ? seen : Eigen::Vector3d(seen - across);
        else
          across = across == Eigen::Vector3d::UnitX() ? Eigen::Vector3d(-seen)
                                                      : Eigen::Vector3d(across - seen);
      }
      Eigen::Matrix3d frame;
      frame.col(1) = up.norm() > 1e-9 ? up.normalized() : Eigen::Vector3d::UnitY();
      Eigen::Vector3d x = across - across.dot(frame.col(1)) * frame.col(1);
      if (x.norm() < 1e-9) x = frame.col(1).unitOrthogonal();
      frame.col(0) = x.normalized();
      frame.col(2) = frame.col(0).cross(frame.col(1));
      global[i] = Eigen::Quaterniond(frame).normalized();
    }
  }
}

void BvhSkeleton::solve(const JointPositions& joints_mm, std::vector<double>& channels) const {
  thread_local std::vector<Eigen::Quaterniond> global;
  solve_rotations(joints_mm, global);
  const bool unwrap_angles = static_cast<int>(channels.size()) == num_channels_;
  channels.resize(static_cast<size_t>(num_channels_));
  size_t c = 0;
  const Eigen::Vector3d root = to_bvh(joints_mm[static_cast<size_t>(nodes_[0].joint)]);
  for (int k = 0; k < 3; ++k) channels[c++] = root[k];
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    if (n.end_site) continue;
    const Eigen::Quaterniond local =
        n.parent < 0 ? global[i] : global[static_cast<size_t>(n.parent)].conjugate() * global[i];
    const Eigen::Vector3d zxy = euler_zxy(local.toRotationMatrix()) * kDeg;
    for (int k = 0; k < 3; ++k, ++c)
      channels[c] = unwrap_angles ? unwrap(zxy[k], channels[c]) : zxy[k];
  }
}

void BvhSkeleton::forward(const std::vector<double>& channels,
                          std::vector<Eigen::Vector3d>& positions_mm) const {
  HULLPOSE_ASSERT(static_cast<int>(channels.size()) == num_channels_);
  std::vector<Eigen::Quaterniond> global(nodes_.size());
  std::vector<Eigen::Vector3d> pos(nodes_.size());
  size_t c = 3;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    if (n.parent < 0) {
      pos[i] = Eigen::Vector3d(channels[0], channels[1], channels[2]);
      global[i] = from_euler_zxy_deg(channels[c], channels[c + 1], channels[c + 2]);
      c += 3;
      continue;
    }
    const auto parent = static_cast<size_t>(n.parent);
    pos[i] = pos[parent] + global[parent] * n.offset;
    if (n.end_site) {
      global[i] = global[parent];
    } else {
      global[i] =
          global[parent] * from_euler_zxy_deg(channels[c], channels[c + 1], channels[c + 2]);
      c += 3;
    }
  }
  positions_mm.resize(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i) positions_mm[i] = from_bvh(pos[i]);
}

void BvhSkeleton::format_line(const std::vector<double>& channels, std::string& line) {
  line.resize(channels.size() * 64 + 1);  // any finite float in fixed notation fits
  char* out = line.data();
  char* const end = line.data() + line.size();
  for (size_t i = 0; i < channels.size(); ++i) {
    if (i) *out++ = ' ';
    out = std::to_chars(out, end, channels[i], std::chars_format::fixed, 6).ptr;
  }
  *out++ = '\n';
  line.resize(static_cast<size_t>(out - line.data()));
}

}  // namespace hullpose::skeleton_io
