#pragma once
// Rigs from other tools' calibrations, converted into our world (mm, z up, floor z = 0) and
// camera model (common/camera.hpp):
//  - 3x4 projection matrices (pixel = P [X Y Z 1]ᵀ), split by RQ into K, R, t. Our model has no
//    skew: the skew found is reported with the largest pixel shift dropping it causes.
//  - OpenCV FileStorage files (camera matrix, distortion, Rodrigues vector or 3x3 rotation,
//    translation; world -> camera as cv::solvePnP), e.g. the Utrecht course data's config.xml.
// The source world's units, up axis and floor height are stated by the user (SourceWorld); no
// file format carries them reliably.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hullpose/common/camera.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::import {

// How the source world's coordinates map onto ours.
struct SourceWorld {
  double mm_per_unit = 1;       // "m" = 1000, "cm" = 10, "mm" = 1, "in" = 25.4
  Eigen::Vector3d up{0, 0, 1};  // the source's up axis, a signed unit axis (+y, -z, ...)
  double floor = 0;             // the floor's coordinate along `up`, source units

  // Ours from source: x_ours = rotation() * x_src * mm_per_unit - floor_mm e_z, a proper rotation
  // that takes `up` to +z (and the first other source axis to +x).
  Eigen::Matrix3d rotation() const;
  // Source world -> camera (source units) to ours (world mm -> camera mm).
  void convert(const Eigen::Matrix3d& R_src, const Eigen::Vector3d& t_src, Eigen::Matrix3d& R,
               Eigen::Vector3d& t) const;
};
// "m", "cm", "mm", "in"; throws hullpose::Error naming the option otherwise.
double parse_units(const std::string& text);
// "x", "+y", "-z", ...; throws hullpose::Error otherwise.
Eigen::Vector3d parse_axis(const std::string& text);

// K, R, t of a projection matrix (any non-zero scale, either sign).
struct ProjectionSplit {
  Eigen::Matrix3d K;  // upper triangular, K(2,2) = 1, positive focal lengths
  Eigen::Matrix3d R;  // world -> camera, a rotation
  Eigen::Vector3d t;  // world -> camera, source units
  double skew = 0;    // K(0,1), pixels
};
// Throws hullpose::Error (naming `what`) if the left 3x3 block is singular or not finite.
ProjectionSplit split_projection(const Eigen::Matrix<double, 3, 4>& P, const std::string& what);
Eigen::Matrix<double, 3, 4> read_projection(const std::filesystem::path& path);  // 12 numbers

// One imported camera and what the import noticed about it (printed by the tool).
struct ImportedCamera {
  CameraModel camera;
  std::filesystem::path source;
  double skew_px = 0;          // projection matrices: K(0,1)
  double skew_shift_px = 0;    // largest pixel shift over the image from dropping the skew
  double rotation_repair = 0;  // OpenCV 3x3 rotations: deviation repaired (repair_rotation)
};

// From an OpenCV FileStorage file; throws hullpose::Error naming the file and the field.
ImportedCamera read_opencv_camera(const std::filesystem::path& path);

enum class SourceKind { kProjection, kOpenCv };

struct RigImportOptions {
  SourceKind kind = SourceKind::kProjection;
  std::string pattern;        // path with {N} for the camera number (pattern.hpp)
  std::vector<int> cameras;   // camera numbers; empty = every N in 0..63 whose file exists
  int width = 0, height = 0;  // image size (neither format stores it)
  SourceWorld world;
  std::string rig_id = "imported";
  std::optional<CaptureVolume> volume;  // default: the box every camera sees (common_view_volume)
  // Or a box of this size (x, y, z) on the floor, centred under the point nearest to every
  // camera's optical axis: a rig's cameras aim at the middle of the capture area, and a volume
  // the size of the subject's space carves finer and with fewer ghosts than all the shared view.
  std::optional<Eigen::Vector3d> volume_size_mm;
  double max_height_mm = 0;  // > 0: the default volume stops at this height
};

struct RigImport {
  Rig rig;
  std::vector<ImportedCamera> cameras;
};

// The point nearest (least squares) to every camera's optical axis, world mm.
Eigen::Vector3d axes_meeting_point(const std::vector<CameraModel>& cameras);

// Reads and converts every camera; the capture volume as given or computed. The camera number N
// becomes the camera id. Throws hullpose::Error naming the file and the field.
RigImport import_rig(const RigImportOptions& options);

}  // namespace hullpose::import
