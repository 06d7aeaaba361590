#include "hullpose/common/rig.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <opencv2/core.hpp>
#include <set>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

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

// --- reading ---------------------------------------------------------------------------

struct Reader {
  std::string file;

  cv::FileNode need(const cv::FileNode& parent, const char* key, const std::string& ctx) const {
    cv::FileNode n = parent[key];
    HULLPOSE_THROW_UNLESS(!n.empty() && !n.isNone(), file << ": " << ctx
                                                          << (ctx.empty() ? "" : ": ")
                                                          << "missing field '" << key << "'");
    return n;
  }
  double real(const cv::FileNode& parent, const char* key, const std::string& ctx) const {
    cv::FileNode n = need(parent, key, ctx);
    HULLPOSE_THROW_UNLESS(n.isReal() || n.isInt(),
                          file << ": " << ctx << ": field '" << key << "' must be a number");
    return static_cast<double>(n);
  }
  int integer(const cv::FileNode& parent, const char* key, const std::string& ctx) const {
    cv::FileNode n = need(parent, key, ctx);
    HULLPOSE_THROW_UNLESS(n.isInt(),
                          file << ": " << ctx << ": field '" << key << "' must be an integer");
    return static_cast<int>(n);
  }
  std::vector<double> reals(const cv::FileNode& parent, const char* key, size_t count,
                            const std::string& ctx) const {
    cv::FileNode n = need(parent, key, ctx);
    HULLPOSE_THROW_UNLESS(n.isSeq() && n.size() == count, file << ": " << ctx << ": field '" << key
                                                               << "' must be a list of " << count
                                                               << " numbers");
    std::vector<double> out;
    for (const auto& item : n) {
      HULLPOSE_THROW_UNLESS(item.isReal() || item.isInt(),
                            file << ": " << ctx << ": field '" << key << "' must hold numbers");
      out.push_back(static_cast<double>(item));
    }
    return out;
  }
};

}  // namespace

double repair_rotation(Eigen::Matrix3d& R) {
  const double deviation = orthonormality_error(R);
  if (!R.allFinite() || deviation <= 1e-10 || deviation > kMaxRotationRepair ||
      R.determinant() <= 0)
    return 0;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  R = svd.matrixU() * svd.matrixV().transpose();
  return deviation;
}

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

Rig load_rig(const std::filesystem::path& path) {
  const std::string file = path.string();
  HULLPOSE_THROW_UNLESS(std::filesystem::exists(path), file << ": rig file not found");
  cv::FileStorage fs;
  try {
    fs.open(file, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    HULLPOSE_THROW(file << ": not a readable YAML rig file: " << e.err);
  }
  HULLPOSE_THROW_UNLESS(fs.isOpened(), file << ": cannot open rig file");
  const Reader rd{file};
  const cv::FileNode root = fs.root();

  const int version = rd.integer(root, "version", "");
  HULLPOSE_THROW_UNLESS(version == Rig::kFormatVersion, file << ": unknown rig file version "
                                                             << version << " (this build reads "
                                                             << Rig::kFormatVersion << ")");
  Rig rig;
  const cv::FileNode id = rd.need(root, "rig_id", "");
  HULLPOSE_THROW_UNLESS(id.isString(), file << ": field 'rig_id' must be a string");
  rig.rig_id = static_cast<std::string>(id);

  const cv::FileNode vol = rd.need(root, "capture_volume", "");
  const auto vmin = rd.reals(vol, "min_mm", 3, "capture_volume");
  const auto vmax = rd.reals(vol, "max_mm", 3, "capture_volume");
  rig.volume.min_mm = Eigen::Vector3d(vmin[0], vmin[1], vmin[2]);
  rig.volume.max_mm = Eigen::Vector3d(vmax[0], vmax[1], vmax[2]);

  const cv::FileNode cams = rd.need(root, "cameras", "");
  HULLPOSE_THROW_UNLESS(cams.isSeq(), file << ": field 'cameras' must be a list");
  int index = 0;
  for (const auto& node : cams) {
    const std::string ctx = "cameras[" + std::to_string(index++) + "]";
    CameraModel c;
    c.id = rd.integer(node, "id", ctx);
    const std::string cctx = "camera " + std::to_string(c.id);
    if (!node["name"].empty()) c.name = static_cast<std::string>(node["name"]);
    c.width = rd.integer(node, "width", cctx);
    c.height = rd.integer(node, "height", cctx);
    c.fx = rd.real(node, "fx", cctx);
    c.fy = rd.real(node, "fy", cctx);
    c.cx = rd.real(node, "cx", cctx);
    c.cy = rd.real(node, "cy", cctx);
    const auto d = rd.reals(node, "dist", 5, cctx);
    std::copy(d.begin(), d.end(), c.dist.begin());
    const auto r = rd.reals(node, "R", 9, cctx);
    c.R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r.data());
    if (const double deviation = repair_rotation(c.R); deviation > 0) {
      HULLPOSE_LOG(RigFile, Warn) << file << ": " << cctx << ": R is off orthonormal by "
                                  << deviation
                                  << " (max |R^T R - I|), replaced by the nearest rotation";
    }
    const auto t = rd.reals(node, "t_mm", 3, cctx);
    c.t = Eigen::Vector3d(t[0], t[1], t[2]);
    rig.cameras.push_back(std::move(c));
  }
  try {
    rig.validate();
  } catch (const Error& e) {
    HULLPOSE_THROW(file << ": " << e.what());
  }
  return rig;
}

void save_rig(const Rig& rig, const std::filesystem::path& path) {
  rig.validate();
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
