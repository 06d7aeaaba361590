#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "hullpose/common/check.hpp"
#include "hullpose/common/rig.hpp"

using namespace hullpose;
namespace fs = std::filesystem;

namespace {

Rig sample_rig() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  Rig rig;
  rig.rig_id = "test-rig";
  rig.volume = {{-1000.125, -1000, 0}, {1000, 1000.5, 2100}};
  for (int i = 0; i < 8; ++i) {
    CameraModel c;
    c.id = i;
    c.name = "cam" + std::to_string(i);
    c.width = 800;
    c.height = 600;
    c.fx = 700 + u(rng);  // full-precision doubles: the file must keep every bit
    c.fy = 701 + u(rng);
    c.cx = 400 + u(rng);
    c.cy = 300 + u(rng);
    c.dist = {0.1 * u(rng), 0.01 * u(rng), 1e-4 * u(rng), 1e-4 * u(rng), 1e-3 * u(rng)};
    c.R = Eigen::AngleAxisd(2 * M_PI * i / 8 + 0.1 * u(rng), Eigen::Vector3d::UnitZ())
              .toRotationMatrix();
    // z first: the order x86-64 GCC evaluated one call's arguments in (unspecified in C++).
    const double tz = 4000 + u(rng), ty = u(rng), tx = u(rng);
    c.t = Eigen::Vector3d(tx, ty, tz);
    rig.cameras.push_back(c);
  }
  return rig;
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("hullpose-rig-" + std::to_string(::getpid()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
void write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

// Loads the sample rig's file with the first occurrence of `from` replaced by `to` and returns
// the error message, or "" if it loaded; with through_bracket, everything up to
// and including the next ']' (a list may span lines) is replaced.
// Camera 0 comes first in the file.
std::string load_error_after(const TempDir& dir, const std::string& from, const std::string& to,
                             bool through_bracket = false) {
  const fs::path good = dir.path / "good.yaml", bad = dir.path / "bad.yaml";
  save_rig(sample_rig(), good);
  std::string text = read(good);
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, through_bracket ? text.find(']', at) + 1 - at : from.size(), to);
  write(bad, text);
  try {
    load_rig(bad);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("rig YAML round-trips exactly") {
  TempDir dir;
  const Rig rig = sample_rig();
  save_rig(rig, dir.path / "rig.yaml");
  const Rig back = load_rig(dir.path / "rig.yaml");
  CHECK(back == rig);
  save_rig(back, dir.path / "rig2.yaml");
  CHECK(read(dir.path / "rig.yaml") == read(dir.path / "rig2.yaml"));
}

TEST_CASE("bad rig files give errors naming the camera and field") {
  TempDir dir;
  using Catch::Contains;
  CHECK_THAT(load_error_after(dir, "fx: ", "fx: -"),
             Contains("camera 0") && Contains("fx must be positive"));
  CHECK_THAT(load_error_after(dir, "fy: ", "fy: .nan #"),
             Contains("bad.yaml:16: cameras[0].fy: must be a number"));
  CHECK_THAT(load_error_after(dir, "id: 3", "id: 2"), Contains("duplicate camera id 2"));
  CHECK_THAT(load_error_after(dir, "version: 1", "version: 7"),
             Contains("unknown rig file version 7"));
  CHECK_THAT(load_error_after(dir, "version: 1", "versio: 1"),
             Contains("bad.yaml:3: version: missing (required)"));
  CHECK_THAT(load_error_after(dir, "cx: ", "cxx: "), Contains("cameras[0].cx: missing (required)"));
  CHECK_THAT(load_error_after(dir, "width: 800", "width: 0"),
             Contains("camera 0") && Contains("image size"));
  CHECK_THAT(load_error_after(dir, "dist: [ ", "dist: [ 1., "),
             Contains("cameras[0].dist: must be a list of 5 numbers"));
  CHECK_THAT(load_error_after(dir, "max_mm: [ ", "max_mm: [ -5000., "), Contains("capture_volume"));
  // A scaled rotation is not a rotation.
  CHECK_THAT(load_error_after(dir, "R: [ ", "R: [ 2., 0., 0., 0., 1., 0., 0., 0., 1. ]", true),
             Contains("camera 0") && Contains("R is not a rotation"));
  CHECK_THAT(load_error_after(dir, "t_mm: [ ", "t_mm: [ .inf, "), Contains("cameras[0].t_mm"));
}

TEST_CASE("unreadable rig files are reported with their path") {
  TempDir dir;
  using Catch::Contains;
  CHECK_THROWS_WITH(load_rig(dir.path / "nope.yaml"),
                    Contains("nope.yaml") && Contains("not found"));
  write(dir.path / "garbage.yaml", "{{{ this is not: yaml ]]\n");
  CHECK_THROWS_WITH(load_rig(dir.path / "garbage.yaml"), Contains("garbage.yaml"));
  write(dir.path / "empty.yaml", "");
  CHECK_THROWS_AS(load_rig(dir.path / "empty.yaml"), Error);
}

TEST_CASE("find returns the camera by id") {
  const Rig rig = sample_rig();
  REQUIRE(rig.find(5) != nullptr);
  CHECK(rig.find(5)->name == "cam5");
  CHECK(rig.find(42) == nullptr);
}
