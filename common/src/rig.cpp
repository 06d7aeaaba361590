#include "hullpose/common/rig.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <opencv2/core.hpp>
#include <set>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/yaml.hpp"

namespace hullpose {

HULLPOSE_LOG_CATEGORY(RigFile, "rig")

namespace {

double orthonormality_error(const Eigen::Matrix3d& R) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

bool finite(double v) {
  return std::isfinite(v);
}
template <typename Derived>
bool all_finite(const Eigen::MatrixBase<Derived>& m) {
  return m.allFinite();
}

std::string where(const CameraModel& c) {
  return "camera " + std::to_string(c.id);
}

void validate_camera(const CameraModel& c) {
  HULLPOSE_THROW_UNLESS(c.id >= 0 && c.id < 64, "camera id " << c.id << " must be in 0..63");
  HULLPOSE_THROW_UNLESS(c.width > 0 && c.width <= Rig::kMaxImageSide && c.height > 0 &&
                            c.height <= Rig::kMaxImageSide,
                        where(c) << ": image size " << c.width << "x" << c.height
                                 << " must be positive and at most " << Rig::kMaxImageSide);
  for (auto [field, value] : {std::pair{"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}})
    HULLPOSE_THROW_UNLESS(finite(value), where(c) << ": " << field << " is not finite");
  HULLPOSE_THROW_UNLESS(c.fx > 0, where(c) << ": fx must be positive, got " << c.fx);
  HULLPOSE_THROW_UNLESS(c.fy > 0, where(c) << ": fy must be positive, got " << c.fy);
  for (size_t i = 0; i < c.dist.size(); ++i)
    HULLPOSE_THROW_UNLESS(finite(c.dist[i]), where(c) << ": dist[" << i << "] is not finite");
  HULLPOSE_THROW_UNLESS(all_finite(c.R), where(c) << ": R has a non-finite entry");
  HULLPOSE_THROW_UNLESS(all_finite(c.t), where(c) << ": t has a non-finite entry");
  const double orth = orthonormality_error(c.R);
  HULLPOSE_THROW_UNLESS(orth < 1e-6 && c.R.determinant() > 0,
                        where(c) << ": R is not a rotation (|R^T R - I| = " << orth
                                 << ", det = " << c.R.determinant() << ")");
}

}  // namespace

const CameraModel* Rig::find(int camera_id) const {
  for (const auto& c : cameras)
    if (c.id == camera_id) return &c;
  return nullptr;
}

void Rig::validate() const {
  HULLPOSE_THROW_UNLESS(!rig_id.empty(), "rig_id must not be empty");
  HULLPOSE_THROW_UNLESS(!cameras.empty(), "rig '" << rig_id << "' has no cameras");
  std::set<int> ids;
  for (const auto& c : cameras) {
    validate_camera(c);
    HULLPOSE_THROW_UNLESS(ids.insert(c.id).second, "duplicate camera id " << c.id);
  }
  HULLPOSE_THROW_UNLESS(all_finite(volume.min_mm) && all_finite(volume.max_mm),
                        "capture_volume has a non-finite bound");
  HULLPOSE_THROW_UNLESS((volume.max_mm.array() > volume.min_mm.array()).all(),
                        "capture_volume: max must exceed min on every axis");
}

double repair_rotation(Eigen::Matrix3d& R) {
  const double deviation = orthonormality_error(R);
  if (!R.allFinite() || deviation <= 1e-10 || deviation > kMaxRotationRepair ||
      R.determinant() <= 0)
    return 0;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  R = svd.matrixU() * svd.matrixV().transpose();
  return deviation;
}

namespace {

Rig read_rig(const yaml::Document& doc, const std::string& file) {
  const yaml::Node root = doc.root();
  const yaml::Node version = root.need("version");
  HULLPOSE_THROW_UNLESS(version.integer() == Rig::kFormatVersion,
                        version.where() << ": unknown rig file version " << version.integer()
                                        << " (this build reads " << Rig::kFormatVersion << ")");
  Rig rig;
  rig.rig_id = root.need("rig_id").string();
  root.get("units");  // a note for readers of the file, not read

  const yaml::Node vol = root.need("capture_volume");
  const auto vmin = vol.need("min_mm").reals(3);
  const auto vmax = vol.need("max_mm").reals(3);
  rig.volume.min_mm = Eigen::Vector3d(vmin[0], vmin[1], vmin[2]);
  rig.volume.max_mm = Eigen::Vector3d(vmax[0], vmax[1], vmax[2]);

  for (const yaml::Node& node : root.need("cameras").items()) {
    CameraModel c;
    c.id = node.need("id").integer();
    if (const auto name = node.get("name")) c.name = name->text();
    c.width = node.need("width").integer();
    c.height = node.need("height").integer();
    c.fx = node.need("fx").real();
    c.fy = node.need("fy").real();
    c.cx = node.need("cx").real();
    c.cy = node.need("cy").real();
    const auto d = node.need("dist").reals(5);
    std::copy(d.begin(), d.end(), c.dist.begin());
    const auto r = node.need("R").reals(9);
    c.R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r.data());
    if (const double deviation = repair_rotation(c.R); deviation > 0) {
      HULLPOSE_LOG(RigFile, Warn) << file << ": camera " << c.id << ": R is off orthonormal by "
                                  << deviation
                                  << " (max |R^T R - I|), replaced by the nearest rotation";
    }
    const auto t = node.need("t_mm").reals(3);
    c.t = Eigen::Vector3d(t[0], t[1], t[2]);
    rig.cameras.push_back(std::move(c));
  }
  doc.check_all_read();
  try {
    rig.validate();
  } catch (const Error& e) {
    HULLPOSE_THROW(file << ": " << e.what());
  }
  return rig;
}

}  // namespace

Rig load_rig(const std::filesystem::path& path) {
  HULLPOSE_THROW_UNLESS(std::filesystem::exists(path), path.string() << ": rig file not found");
  return read_rig(yaml::Document::load(path), path.string());
}

Rig parse_rig(const std::string& text, const std::string& name) {
  return read_rig(yaml::Document::parse(text, name), name);
}

void save_rig(const Rig& rig, const std::filesystem::path& path) {
  rig.validate();
  // Written with OpenCV's YAML writer: the format rig files have always had (docs/rig-file.md);
  // load_rig reads it with yaml-cpp like any YAML.
  cv::FileStorage fs(path.string(), cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  HULLPOSE_THROW_UNLESS(fs.isOpened(), path.string() << ": cannot write rig file");
  auto write_seq = [&fs](const char* key, const double* values, int n) {
    fs << key << "[:";
    for (int i = 0; i < n; ++i) fs << values[i];
    fs << "]";
  };
  fs << "version" << Rig::kFormatVersion;
  fs << "rig_id" << rig.rig_id;
  fs << "units"
     << "mm; world z up, floor z=0; R,t map world to camera";
  fs << "capture_volume"
     << "{";
  write_seq("min_mm", rig.volume.min_mm.data(), 3);
  write_seq("max_mm", rig.volume.max_mm.data(), 3);
  fs << "}";
  fs << "cameras"
     << "[";
  for (const auto& c : rig.cameras) {
    fs << "{";
    fs << "id" << c.id << "name" << c.name << "width" << c.width << "height" << c.height;
    fs << "fx" << c.fx << "fy" << c.fy << "cx" << c.cx << "cy" << c.cy;
    write_seq("dist", c.dist.data(), 5);
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> r = c.R;
    write_seq("R", r.data(), 9);
    write_seq("t_mm", c.t.data(), 3);
    fs << "}";
  }
  fs << "]";
}

bool operator==(const CameraModel& a, const CameraModel& b) {
  return a.id == b.id && a.name == b.name && a.width == b.width && a.height == b.height &&
         a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.dist == b.dist &&
         a.R == b.R && a.t == b.t;
}

bool operator==(const Rig& a, const Rig& b) {
  return a.rig_id == b.rig_id && a.cameras == b.cameras && a.volume.min_mm == b.volume.min_mm &&
         a.volume.max_mm == b.volume.max_mm;
}

}  // namespace hullpose
