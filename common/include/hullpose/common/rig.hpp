#pragma once
// The rig: every camera, the capture volume and the rig id. Shared by the camera nodes, the
// fusion host, the synthetic rig and the calibration tool. Stored as YAML (read with yaml-cpp,
// common/yaml.hpp; written by OpenCV's YAML writer), format documented in docs/rig-file.md.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "hullpose/common/camera.hpp"

namespace hullpose {

struct CaptureVolume {
  Eigen::Vector3d min_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d size_mm() const { return max_mm - min_mm; }
};

struct Rig {
  static constexpr int kFormatVersion = 1;
  static constexpr int kMaxImageSide = 8192;

  std::string rig_id;
  std::vector<CameraModel> cameras;
  CaptureVolume volume;

  // The camera with this id, or nullptr.
  const CameraModel* find(int camera_id) const;
  // Throws hullpose::Error naming the camera and field at fault (see rig.cpp for the rules).
  void validate() const;
};

// Other tools write rotations with few decimals (6 are common), a little off orthonormal. If
// max|RᵀR - I| is above 1e-10 (more than a computed rotation's rounding, so rigs we write still
// round-trip exactly) and at most kMaxRotationRepair, R is replaced by the nearest rotation (SVD)
// and the deviation is returned; otherwise R is left alone and 0 returned (a gross error or a
// reflection stays for validate() to refuse).
inline constexpr double kMaxRotationRepair = 1e-3;
double repair_rotation(Eigen::Matrix3d& R);

// Throws hullpose::Error naming the file, camera and field on any problem; the result is
// validated. Rotations slightly off orthonormal are repaired (repair_rotation) with a warning.
Rig load_rig(const std::filesystem::path& path);
// The same from the file's text; `name` stands for the file in errors (fuzz_rig_reader).
Rig parse_rig(const std::string& text, const std::string& name);
// Validates, then writes; doubles are written so that load_rig(save_rig(r)) == r exactly.
void save_rig(const Rig& rig, const std::filesystem::path& path);

bool operator==(const CameraModel& a, const CameraModel& b);
bool operator==(const Rig& a, const Rig& b);

}  // namespace hullpose
