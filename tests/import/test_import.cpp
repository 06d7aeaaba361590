// hullpose-import: projection-matrix split, OpenCV FileStorage cameras, the source world's
// conversion, both shared captures, rotation repair and the silhouette dataset import.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <sstream>

#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/import/cli.hpp"
#include "hullpose/import/pattern.hpp"
#include "hullpose/import/rig_import.hpp"
#include "hullpose/import/silhouette_import.hpp"

using namespace hullpose;
using namespace hullpose::import;
namespace fs = std::filesystem;
using Catch::Contains;

namespace {

const fs::path kReal = fs::path(HULLPOSE_SHARED_DIR) / "data/real";

struct TempDir {
  fs::path path;
  TempDir() {
    path =
        fs::temp_directory_path() / ("hullpose_import_" + std::to_string(std::random_device{}()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

void write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

RigImportOptions crane_options() {
  RigImportOptions o;
  o.kind = SourceKind::kProjection;
  o.pattern = (kReal / "vlasic-crane/calibration/camera{N}.P").string();
  o.width = 1600;
  o.height = 1200;
  o.world = {1000, Eigen::Vector3d::UnitY(), 0};
  return o;
}

RigImportOptions utrecht_options() {
  RigImportOptions o;
  o.kind = SourceKind::kOpenCv;
  o.pattern = (kReal / "utrecht-4cam/cam{N}/config.xml").string();
  o.width = 644;
  o.height = 486;
  o.world = {1, -Eigen::Vector3d::UnitZ(), 0};
  return o;
}

int run(const std::vector<std::string>& args, std::string& out, std::string& err) {
  std::vector<const char*> argv{"hullpose-import"};
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream o, e;
  const int rc = run_tool(
      "hullpose-import", static_cast<int>(argv.size()), argv.data(),
      [&o](int c, const char* const* v) { return run_cli(c, v, o); }, e);
  out = o.str();
  err = e.str();
  return rc;
}

}  // namespace

TEST_CASE("patterns expand camera and frame numbers, padded to the field's width") {
  CHECK(expand("cam{N}/x_{FFFF}.png", 'N', 7) == "cam7/x_{FFFF}.png");
  CHECK(expand(expand("cam{NN}/x_{FFFF}.png", 'N', 7), 'F', 42) == "cam07/x_0042.png");
  CHECK(expand("a{F}", 'F', 123) == "a123");
  CHECK_THROWS_WITH(expand("camera.P", 'N', 1), Contains("no {N} field"));
}

TEST_CASE("known K, R, t -> P -> back, at any scale and sign, with the skew reported") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  // Draws in sequence (constructor arguments are evaluated in an unspecified order).
  auto u3 = [&] {
    const double x = u(rng), y = u(rng);
    return Eigen::Vector3d(x, y, u(rng));
  };
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Matrix3d K;
    K << 900 + 300 * u(rng), 0.8 * u(rng), 640 + 20 * u(rng), 0, 905 + 300 * u(rng),
        480 + 20 * u(rng), 0, 0, 1;
    const double angle = M_PI * u(rng);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, u3().normalized()).toRotationMatrix();
    const Eigen::Vector3d t =
        Eigen::Vector3d(2000, 2000, 1000).cwiseProduct(u3()) + Eigen::Vector3d(0, 0, 3000);
    Eigen::Matrix<double, 3, 4> P;
    P << K * R, K * t;
    const double scale = (trial % 2 ? -1 : 1) * std::pow(10.0, 3 * u(rng));
    const ProjectionSplit s = split_projection(scale * P, "test");
    CHECK((s.K - K).cwiseAbs().maxCoeff() < 1e-8 * K.norm());
    CHECK((s.R - R).cwiseAbs().maxCoeff() < 1e-10);
    CHECK((s.t - t).norm() < 1e-8 * t.norm());
    CHECK(s.skew == Approx(K(0, 1)).margin(1e-8));
  }
  Eigen::Matrix<double, 3, 4> singular = Eigen::Matrix<double, 3, 4>::Zero();
  singular(0, 0) = 1;
  CHECK_THROWS_WITH(split_projection(singular, "cam.P"), Contains("cam.P") && Contains("singular"));
}

TEST_CASE("the source world's units, up axis and floor map onto ours without moving a pixel") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  auto u3 = [&] {
    const double x = u(rng), y = u(rng);
    return Eigen::Vector3d(x, y, u(rng));
  };
  for (const char* up : {"x", "+y", "-y", "z", "-z", "-x"}) {
    const SourceWorld world{1000, parse_axis(up), 0.3};
    const Eigen::Matrix3d A = world.rotation();
    CHECK((A * A.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    CHECK(A.determinant() == Approx(1));
    CHECK((A * world.up - Eigen::Vector3d::UnitZ()).norm() < 1e-12);  // their up is our z
    const double angle = 3 * u(rng);
    Eigen::Vector3d axis = u3();
    axis.z() = 1;
    const Eigen::Matrix3d R_src = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    const Eigen::Vector3d t_src = u3() + Eigen::Vector3d(0, 0, 4);  // metres
    CameraModel c;
    c.fx = c.fy = 1000;
    c.width = c.height = 100000;
    world.convert(R_src, t_src, c.R, c.t);
    for (int i = 0; i < 10; ++i) {
      const Eigen::Vector3d x_src = u3();
      const Eigen::Vector3d cam_src = R_src * x_src + t_src;
      const Eigen::Vector3d x_ours = 1000 * (A * x_src) - Eigen::Vector3d(0, 0, 300);
      CHECK((c.R * x_ours + c.t - 1000 * cam_src).norm() < 1e-9);
      // The floor (up coordinate 0.3 m) is at our z = 0.
      CHECK((1000 * (A * (world.up * 0.3))).z() - 300 == Approx(0).margin(1e-9));
    }
  }
  CHECK_THROWS_WITH(parse_axis("w"), Contains("--up"));
  CHECK_THROWS_WITH(parse_units("furlong"), Contains("--units"));
}

TEST_CASE("the crane's projection matrices import: cameras on a ring 2.75 m up, pixels kept") {
  const RigImport r = import_rig(crane_options());
  REQUIRE(r.rig.cameras.size() == 8);
  for (const ImportedCamera& ic : r.cameras) {
    const CameraModel& c = ic.camera;
    const Eigen::Vector3d centre = c.centre();
    CHECK(centre.z() == Approx(2750).margin(50));
    CHECK(centre.head<2>().norm() > 2000);
    CHECK(std::abs(ic.skew_px) < 1);
    CHECK(ic.skew_shift_px < 0.6);
    // A point 1 m above the floor centre projects where P puts it (y-up metres), up to the skew.
    const Eigen::Matrix<double, 3, 4> P = read_projection(ic.source);
    const Eigen::Vector3d p = P * Eigen::Vector4d(0.1, 1.0, -0.2, 1);
    const auto px = c.project({100, 200, 1000});
    REQUIRE(px);
    CHECK((*px - p.head<2>() / p.z()).norm() <= ic.skew_shift_px + 1e-6);
  }
  CHECK(r.rig.volume.min_mm.z() == 0);
  CHECK(r.rig.volume.max_mm.z() > 1900);  // room for the 1.82 m subject
}

TEST_CASE(
    "Utrecht's OpenCV config.xml files import: cameras above the floor, pixels as "
    "cv::projectPoints") {
  const RigImport r = import_rig(utrecht_options());
  REQUIRE(r.rig.cameras.size() == 4);
  for (const ImportedCamera& ic : r.cameras) {
    const CameraModel& c = ic.camera;
    CHECK(c.centre().z() > 1000);  // z pointed down into the floor: the cameras are up
    CHECK(c.dist[0] != 0);
    cv::FileStorage fs(ic.source.string(), cv::FileStorage::READ);
    cv::Mat K, D, rvec, tvec;
    fs["CameraMatrix"] >> K;
    fs["DistortionCoeffs"] >> D;
    fs["Rotation"] >> rvec;
    fs["Translation"] >> tvec;
    // A board point (their frame, mm, z down) and the same point in ours (z up).
    std::vector<cv::Point3d> board{{345, 230, -500}};
    std::vector<cv::Point2d> expect;
    cv::projectPoints(board, rvec, tvec, K, D, expect);
    const auto got = c.project({345, -230, 500});
    REQUIRE(got);
    CHECK((*got - Eigen::Vector2d(expect[0].x, expect[0].y)).norm() < 1e-3);
  }
}

TEST_CASE("rotations a little off orthonormal are repaired on load; gross ones are refused") {
  TempDir dir;
  RigImportOptions o = utrecht_options();
  Rig rig = import_rig(o).rig;
  save_rig(rig, dir.path / "rig.yaml");
  // Rewrite every number with 6 decimals, as other tools do.
  std::ifstream in(dir.path / "rig.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str(), rounded;
  for (size_t i = 0; i < s.size();) {
    if (std::isdigit(static_cast<unsigned char>(s[i])) ||
        (s[i] == '-' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      size_t used = 0;
      const double v = std::stod(s.substr(i), &used);
      const bool real = s.substr(i, used).find_first_of(".e") != std::string::npos;
      char buf[64];
      std::snprintf(buf, sizeof buf, real ? "%.6f" : "%.0f", v);
      rounded += buf;
      i += used;
    } else {
      rounded += s[i++];
    }
  }
  write(dir.path / "rounded.yaml", rounded);
  const Rig back = load_rig(dir.path / "rounded.yaml");
  for (size_t i = 0; i < back.cameras.size(); ++i) {
    const Eigen::Matrix3d& R = back.cameras[i].R;
    CHECK((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((R - rig.cameras[i].R).cwiseAbs().maxCoeff() < 2e-6);
  }
  Eigen::Matrix3d gross = rig.cameras[0].R * 1.01;
  CHECK(repair_rotation(gross) == 0);
  rig.cameras[0].R = gross;
  CHECK_THROWS_WITH(rig.validate(), Contains("camera 1") && Contains("R is not a rotation"));
}

TEST_CASE("bad calibration files name the file and the field") {
  TempDir dir;
  write(dir.path / "camera1.P", "1 2 3 4\n5 6 7 8\n9 10 11\n");
  CHECK_THROWS_WITH(read_projection(dir.path / "camera1.P"),
                    Contains("camera1.P") && Contains("12 numbers"));
  write(dir.path / "camera1.P", "1 2 3 4\n5 6 x 8\n9 10 11 12\n");
  CHECK_THROWS_WITH(read_projection(dir.path / "camera1.P"),
                    Contains("camera1.P") && Contains("'x'"));
  write(dir.path / "config.xml",
        "<?xml version=\"1.0\"?>\n<opencv_storage>\n<CameraMatrix "
        "type_id=\"opencv-matrix\"><rows>3</rows>"
        "<cols>3</cols><dt>d</dt><data>500 0 320 0 500 240 0 0 "
        "1</data></CameraMatrix>\n</opencv_storage>\n");
  CHECK_THROWS_WITH(read_opencv_camera(dir.path / "config.xml"),
                    Contains("config.xml") && Contains("DistortionCoeffs"));
  std::string out, err;
  CHECK(
      run({"rig", "--projections", (dir.path / "camera{N}.P").string(), "--size", "800x600",
           "--units", "m", "--up", "y", "--floor", "0", "--out", (dir.path / "rig.yaml").string()},
          out, err) == 2);
  CHECK_THAT(err, Contains("camera1.P"));
  CHECK(run({"rig", "--projections", (dir.path / "camera{N}.P").string(), "--size", "800x600",
             "--out", "x.yaml"},
            out, err) == 2);
  CHECK_THAT(err, Contains("--units, --up and --floor"));
}

TEST_CASE("crane silhouettes become a dataset; a corrupt mask is that camera missing") {
  TempDir dir;
  const RigImport r = import_rig(crane_options());
  save_rig(r.rig, dir.path / "rig.yaml");
  // A source folder with 3 frames of cameras 1..8, frame 1 of camera 3 truncated, camera 5's frame
  // 2 absent.
  const fs::path src = dir.path / "src";
  fs::create_directories(src);
  for (int f = 0; f < 3; ++f)
    for (int n = 1; n <= 8; ++n) {
      if (n == 5 && f == 2) continue;
      const std::string name = expand(expand("camera{N}_{FFFF}.png", 'N', n), 'F', f);
      fs::copy_file(kReal / "vlasic-crane/silhouettes" / name, src / name);
      if (n == 3 && f == 1) fs::resize_file(src / name, fs::file_size(src / name) / 3);
    }
  std::string out, err;
  const fs::path data = dir.path / "data";
  REQUIRE(run({"silhouettes", "--rig", (dir.path / "rig.yaml").string(), "--pattern",
               (src / "camera{N}_{FFFF}.png").string(), "--out", data.string()},
              out, err) == 0);
  CHECK_THAT(out, Contains("3 frames") && Contains("22 masks") && Contains("1 missing") &&
                      Contains("1 unreadable"));
  const DatasetPaths paths(data);
  CHECK(read_meta(paths.meta()).frames == 3);
  CHECK(load_rig(paths.rig()) == r.rig);
  const cv::Mat m = cv::imread(paths.mask(1, 0).string(), cv::IMREAD_UNCHANGED);
  REQUIRE(m.type() == CV_8UC1);
  CHECK(cv::countNonZero(m) > 10000);
  CHECK(!fs::exists(paths.mask(3, 1)));
  CHECK(!fs::exists(paths.mask(5, 2)));
  // A rig of the wrong image size is an error naming the file and the camera.
  Rig small = r.rig;
  for (auto& c : small.cameras) c.width = 800;
  save_rig(small, dir.path / "small.yaml");
  CHECK(run({"silhouettes", "--rig", (dir.path / "small.yaml").string(), "--pattern",
             (src / "camera{N}_{FFFF}.png").string(), "--out", (dir.path / "d2").string()},
            out, err) == 2);
  CHECK_THAT(err, Contains("camera1_0000.png") && Contains("camera 1"));
}
