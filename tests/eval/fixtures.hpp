#pragma once
// Small ground-truth datasets built in the test itself: a skeleton made from the model's bone
// ratios (so its stature is known exactly) that walks along y, swinging arms and legs.
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "hullpose/common/dataset.hpp"

namespace hullpose::eval::test {

struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& tag)
      : path(std::filesystem::temp_directory_path() /
             ("hullpose-eval-" + tag + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

// Frame `f` of the walk: rig frame, mm, z up, the subject faces -y with its left side at +x.
inline JointPositions walking_pose(int f, double stature_mm) {
  const double phase = 2 * M_PI * f / 30.0, swing = 0.5 * std::sin(phase);
  const Eigen::Vector3d up(0, 0, 1), down(0, 0, -1), left(1, 0, 0), forward(0, -1, 0);
  auto swung = [&](double angle) {
    return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()) * down;
  };
  JointPositions p{};
  auto at = [&](Joint j) -> Eigen::Vector3d& { return p[static_cast<size_t>(index(j))]; };
  at(Joint::Chest) = Eigen::Vector3d(40 * std::sin(phase / 3), -25.0 * f, 0.72 * stature_mm);
  for (const Bone& bone : kBones) {
    Eigen::Vector3d dir;
    switch (bone.child) {
      case Joint::Neck:
      case Joint::Head:
      case Joint::HeadTop:
        dir = up;
        break;
      case Joint::LSho:
        dir = left;
        break;
      case Joint::RSho:
        dir = -left;
        break;
      case Joint::LElb:
      case Joint::LHand:
      case Joint::LFTip:
        dir = swung(-swing);
        break;
      case Joint::RElb:
      case Joint::RHand:
      case Joint::RFTip:
        dir = swung(swing);
        break;
      case Joint::LHip:
        dir = Eigen::Vector3d(0.6, 0, -0.8);
        break;
      case Joint::RHip:
        dir = Eigen::Vector3d(-0.6, 0, -0.8);
        break;
      case Joint::LKne:
      case Joint::LAnk:
        dir = swung(swing);
        break;
      case Joint::RKne:
      case Joint::RAnk:
        dir = swung(-swing);
        break;
      case Joint::LFoot:
      case Joint::RFoot:
        dir = Eigen::Vector3d(0, -0.6, -0.8);
        break;
      case Joint::LToe:
      case Joint::RToe:
        dir = forward;
        break;
      default:
        dir = down;  // the spine
    }
    at(bone.child) = at(bone.parent) + dir * bone.stature_ratio * stature_mm;
  }
  return p;
}

inline std::vector<PoseRecord> walking_truth(int frames, double stature_mm) {
  std::vector<PoseRecord> out;
  for (int f = 0; f < frames; ++f) {
    PoseRecord r;
    r.frame = f;
    r.utime = 1'700'000'000'000'000 + f * 33'333;
    r.joints = walking_pose(f, stature_mm);
    out.push_back(r);
  }
  return out;
}

inline DatasetMeta walking_meta(int frames, double stature_mm) {
  DatasetMeta m;
  m.motion = "walk (test)";
  m.frames = frames;
  m.fps = 30;
  m.start_utime = 1'700'000'000'000'000;
  m.stature_mm = stature_mm;
  m.camera_ids = {0, 1, 2, 3, 4, 5, 6, 7};
  return m;
}

// Writes DIR/meta.json and DIR/ground_truth.csv.
inline void write_dataset(const std::filesystem::path& dir, const std::vector<PoseRecord>& truth,
                          double stature_mm) {
  std::filesystem::create_directories(dir);
  const DatasetPaths paths(dir);
  write_meta(paths.meta(), walking_meta(static_cast<int>(truth.size()), stature_mm));
  write_ground_truth(paths.ground_truth(), truth);
}

inline void write_estimates(const std::filesystem::path& path,
                            const std::vector<PoseRecord>& estimates) {
  EstimateWriter w(path);
  for (const auto& r : estimates) w.write(r);
}

// The same joints with every left joint exchanged for its right twin.
inline JointPositions mirrored(const JointPositions& p, bool arms, bool legs) {
  JointPositions out = p;
  for (int j = 0; j < kNumJoints; ++j) {
    const Joint joint = static_cast<Joint>(j);
    const bool is_arm = joint == Joint::LSho || joint == Joint::RSho || joint == Joint::LElb ||
                        joint == Joint::RElb || joint == Joint::LHand || joint == Joint::RHand ||
                        joint == Joint::LFTip || joint == Joint::RFTip;
    if (mirror(joint) == joint || (is_arm ? !arms : !legs)) continue;
    out[static_cast<size_t>(j)] = p[static_cast<size_t>(index(mirror(joint)))];
  }
  return out;
}

}  // namespace hullpose::eval::test
