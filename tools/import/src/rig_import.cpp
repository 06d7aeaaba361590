#include "hullpose/import/rig_import.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/core/eigen.hpp>

#include "hullpose/calibrate/extrinsics.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/import/pattern.hpp"

namespace hullpose::import {

Eigen::Matrix3d SourceWorld::rotation() const {
  // Rows: our x, y, z axes written in source coordinates.
  const Eigen::Vector3d z = up;
  const Eigen::Vector3d x =
      std::abs(up.x()) > 0.5 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  Eigen::Matrix3d A;
  A.row(0) = x.transpose();
  A.row(1) = z.cross(x).transpose();
  A.row(2) = z.transpose();
  return A;
}

void SourceWorld::convert(const Eigen::Matrix3d& R_src, const Eigen::Vector3d& t_src,
                          Eigen::Matrix3d& R, Eigen::Vector3d& t) const {
  // x_src = Aᵀ (x_ours + floor_mm e_z) / s, so x_cam_mm = s (R_src x_src + t_src)
  //       = R_src Aᵀ x_ours + R_src Aᵀ floor_mm e_z + s t_src.
  const Eigen::Matrix3d A = rotation();
  R = R_src * A.transpose();
  t = mm_per_unit * t_src + R * Eigen::Vector3d(0, 0, floor * mm_per_unit);
}

double parse_units(const std::string& text) {
  if (text == "m") return 1000;
  if (text == "cm") return 10;
  if (text == "mm") return 1;
  if (text == "in") return 25.4;
  HULLPOSE_THROW("--units: expected m, cm, mm or in, got '" << text << "'");
}

Eigen::Vector3d parse_axis(const std::string& text) {
  std::string axis = text;
  double sign = 1;
  if (!axis.empty() && (axis[0] == '+' || axis[0] == '-')) {
    sign = axis[0] == '-' ? -1 : 1;
    axis = axis.substr(1);
  }
  HULLPOSE_THROW_UNLESS(axis == "x" || axis == "y" || axis == "z",
                        "--up: expected an axis such as y, +z or -z, got '" << text << "'");
  return sign * Eigen::Vector3d::Unit(axis[0] - 'x');
}

ProjectionSplit split_projection(const Eigen::Matrix<double, 3, 4>& P_in, const std::string& what) {
  HULLPOSE_THROW_UNLESS(P_in.allFinite(), what << ": the projection matrix has a non-finite entry");
  Eigen::Matrix<double, 3, 4> P = P_in;
  const double det = P.leftCols<3>().determinant();
  HULLPOSE_THROW_UNLESS(std::abs(det) > 1e-12 * std::pow(P.leftCols<3>().norm(), 3),
                        what << ": the left 3x3 block of P is singular (not a finite camera)");
  if (det < 0) P = -P;  // P is defined up to scale: make the scale positive
  // OpenCV's RQ (Givens rotations): M = K' Q with K' upper triangular.
  cv::Matx33d M, Kc, Qc;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M(i, j) = P(i, j);
  cv::RQDecomp3x3(M, Kc, Qc);
  Eigen::Matrix3d K, Q;
  cv::cv2eigen(Kc, K);
  cv::cv2eigen(Qc, Q);
  // RQ is unique up to the signs of K's columns: make K's diagonal positive (det M > 0, so the
  // rotation keeps det +1).
  const Eigen::Vector3d d(K(0, 0) < 0 ? -1 : 1, K(1, 1) < 0 ? -1 : 1, K(2, 2) < 0 ? -1 : 1);
  K = K * d.asDiagonal();
  Q = d.asDiagonal() * Q;
  ProjectionSplit s;
  s.t = K.triangularView<Eigen::Upper>().solve(P.col(3));
  s.K = K / K(2, 2);
  s.R = Q;
  s.skew = s.K(0, 1);
  HULLPOSE_THROW_UNLESS(s.R.determinant() > 0,
                        what << ": P does not split into a rotation (det R < 0)");
  return s;
}

Eigen::Matrix<double, 3, 4> read_projection(const std::filesystem::path& path) {
  std::ifstream in(path);
  HULLPOSE_THROW_UNLESS(in, path.string() << ": cannot open the projection matrix");
  Eigen::Matrix<double, 3, 4> P;
  for (int i = 0; i < 12; ++i) {
    std::string token;
    HULLPOSE_THROW_UNLESS(in >> token, path.string()
                                           << ": expected 12 numbers (3 rows of 4), found " << i);
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    HULLPOSE_THROW_UNLESS(used == token.size() && std::isfinite(v),
                          path.string() << ": entry " << i / 4 << "," << i % 4 << ": '" << token
                                        << "' is not a finite number");
    P(i / 4, i % 4) = v;
  }
  std::string extra;
  HULLPOSE_THROW_UNLESS(!(in >> extra), path.string()
                                            << ": more than 12 numbers ('" << extra << "' ...)");
  return P;
}

namespace {

// The first of `names` present in the file, as a matrix of doubles.
cv::Mat read_matrix(const cv::FileStorage& fs, const std::filesystem::path& path,
                    std::initializer_list<const char*> names) {
  for (const char* name : names) {
    const cv::FileNode node = fs[name];
    if (node.empty() || node.isNone()) continue;
    cv::Mat m;
    try {
      node >> m;
    } catch (const cv::Exception& e) {
      HULLPOSE_THROW(path.string() << ": field '" << name << "' is not a matrix: " << e.err);
    }
    HULLPOSE_THROW_UNLESS(!m.empty() && m.channels() == 1,
                          path.string() << ": field '" << name << "' is not a matrix");
    cv::Mat d;
    m.convertTo(d, CV_64F);
    for (int i = 0; i < d.rows; ++i)
      for (int j = 0; j < d.cols; ++j)
        HULLPOSE_THROW_UNLESS(std::isfinite(d.at<double>(i, j)),
                              path.string() << ": field '" << name << "' has a non-finite entry");
    return d;
  }
  HULLPOSE_THROW(path.string() << ": missing field '" << *names.begin() << "'");
}

}  // namespace

ImportedCamera read_opencv_camera(const std::filesystem::path& path) {
  const std::string file = path.string();
  HULLPOSE_THROW_UNLESS(std::filesystem::exists(path), file << ": not found");
  cv::FileStorage fs;
  try {
    fs.open(file, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    HULLPOSE_THROW(file << ": not a readable OpenCV FileStorage file: " << e.err);
  }
  HULLPOSE_THROW_UNLESS(fs.isOpened(), file << ": cannot open");
  const cv::Mat K = read_matrix(fs, path, {"CameraMatrix", "camera_matrix", "K"});
  const cv::Mat D =
      read_matrix(fs, path, {"DistortionCoeffs", "distortion_coefficients", "dist_coeffs", "D"});
  const cv::Mat Rm = read_matrix(fs, path, {"Rotation", "rvec", "R"});
  const cv::Mat T = read_matrix(fs, path, {"Translation", "tvec", "T"});
  HULLPOSE_THROW_UNLESS(K.rows == 3 && K.cols == 3, file << ": field 'CameraMatrix' must be 3x3");
  HULLPOSE_THROW_UNLESS(T.total() == 3, file << ": field 'Translation' must hold 3 numbers");
  HULLPOSE_THROW_UNLESS(D.total() <= 14,
                        file << ": field 'DistortionCoeffs' has " << D.total() << " numbers");
  ImportedCamera out;
  out.source = path;
  CameraModel& c = out.camera;
  c.fx = K.at<double>(0, 0);
  c.fy = K.at<double>(1, 1);
  c.cx = K.at<double>(0, 2);
  c.cy = K.at<double>(1, 2);
  out.skew_px = K.at<double>(0, 1);
  const cv::Mat d = D.reshape(1, 1);
  for (int i = 0; i < d.cols; ++i) {
    if (i < 5)
      c.dist[static_cast<size_t>(i)] = d.at<double>(0, i);
    else
      HULLPOSE_THROW_UNLESS(d.at<double>(0, i) == 0,
                            file << ": field 'DistortionCoeffs': coefficient " << i
                                 << " is not zero; only k1 k2 p1 p2 k3 are supported");
  }
  Eigen::Matrix3d R;
  if (Rm.total() == 3) {
    cv::Mat r;
    cv::Rodrigues(Rm.reshape(1, 3), r);
    cv::cv2eigen(r, R);
  } else {
    HULLPOSE_THROW_UNLESS(
        Rm.rows == 3 && Rm.cols == 3,
        file << ": field 'Rotation' must be a Rodrigues vector (3) or a 3x3 matrix");
    cv::cv2eigen(Rm, R);
    out.rotation_repair = repair_rotation(R);
  }
  c.R = R;
  c.t = Eigen::Vector3d(T.at<double>(0), T.at<double>(1), T.at<double>(2));
  return out;
}

Eigen::Vector3d axes_meeting_point(const std::vector<CameraModel>& cameras) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const CameraModel& c : cameras) {
    const Eigen::Vector3d d = c.R.row(2).transpose();  // the optical axis in the world
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - d * d.transpose();
    A += P;
    b += P * c.centre();
  }
  HULLPOSE_THROW_UNLESS(std::abs(A.determinant()) > 1e-9,
                        "the cameras' optical axes are parallel: no point where they meet (give "
                        "--volume-min-mm/--volume-max-mm)");
  return A.ldlt().solve(b);
}

RigImport import_rig(const RigImportOptions& o) {
  HULLPOSE_THROW_UNLESS(o.width > 0 && o.height > 0,
                        "--size WxH is needed (neither format stores the image size)");
  std::vector<int> numbers = o.cameras;
  if (numbers.empty())
    for (int n = 0; n < 64; ++n)
      if (std::filesystem::exists(expand(o.pattern, 'N', n))) numbers.push_back(n);
  HULLPOSE_THROW_UNLESS(!numbers.empty(),
                        "no file matches '" << o.pattern << "' for camera numbers 0..63");
  RigImport out;
  out.rig.rig_id = o.rig_id;
  for (int n : numbers) {
    const std::filesystem::path file = expand(o.pattern, 'N', n);
    ImportedCamera ic;
    Eigen::Matrix3d R_src;
    Eigen::Vector3d t_src;
    if (o.kind == SourceKind::kProjection) {
      const ProjectionSplit s = split_projection(read_projection(file), file.string());
      ic.source = file;
      ic.camera.fx = s.K(0, 0);
      ic.camera.fy = s.K(1, 1);
      ic.camera.cx = s.K(0, 2);
      ic.camera.cy = s.K(1, 2);
      ic.skew_px = s.skew;
      R_src = s.R;
      t_src = s.t;
    } else {
      ic = read_opencv_camera(file);
      R_src = ic.camera.R;
      t_src = ic.camera.t;
    }
    CameraModel& c = ic.camera;
    // Dropping the skew moves a pixel by skew * y_normalised; largest at the top or bottom row.
    ic.skew_shift_px = std::abs(ic.skew_px) * std::max(c.cy, o.height - c.cy) / c.fy;
    c.id = n;
    c.name = file.stem().string();
    c.width = o.width;
    c.height = o.height;
    o.world.convert(R_src, t_src, c.R, c.t);
    try {
      Rig one;
      one.rig_id = o.rig_id;
      one.cameras = {c};
      one.volume.max_mm = Eigen::Vector3d::Ones();
      one.validate();
    } catch (const Error& e) {
      HULLPOSE_THROW(file.string() << ": " << e.what());
    }
    out.rig.cameras.push_back(c);
    out.cameras.push_back(ic);
  }
  if (o.volume) {
    out.rig.volume = *o.volume;
  } else if (o.volume_size_mm) {
    const Eigen::Vector3d m = axes_meeting_point(out.rig.cameras), half = *o.volume_size_mm / 2;
    out.rig.volume.min_mm = Eigen::Vector3d(m.x() - half.x(), m.y() - half.y(), 0);
    out.rig.volume.max_mm =
        Eigen::Vector3d(m.x() + half.x(), m.y() + half.y(), o.volume_size_mm->z());
  } else {
    out.rig.volume = calibrate::common_view_volume(out.rig.cameras,
                                                   static_cast<int>(out.rig.cameras.size()), 50);
    if (o.max_height_mm > 0)
      out.rig.volume.max_mm.z() = std::min(out.rig.volume.max_mm.z(), o.max_height_mm);
  }
  out.rig.validate();
  return out;
}

}  // namespace hullpose::import
