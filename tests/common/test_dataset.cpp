#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"

using namespace hullpose;
namespace fs = std::filesystem;

namespace {
struct TempDir {
  fs::path path = fs::temp_directory_path() / ("hullpose-ds-" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() { fs::remove_all(path); }
};
PoseRecord record(int frame, double base) {
  PoseRecord r;
  r.frame = frame;
  r.utime = 1'700'000'000'000'000 + frame * 33'333;
  for (int j = 0; j < kNumJoints; ++j)
    r.joints[static_cast<size_t>(j)] = Eigen::Vector3d(base + j, -base - j, 1000.125 + j);
  return r;
}
}  // namespace

TEST_CASE("dataset paths follow the conventions") {
  DatasetPaths p("/data/x");
  CHECK(p.mask(3, 17) == fs::path("/data/x/cam3/mask_000017.png"));
  CHECK(p.rgb(0, 0) == fs::path("/data/x/cam0/rgb_000000.png"));
  CHECK(p.background(7, 2) == fs::path("/data/x/cam7/background_000002.png"));
}

TEST_CASE("meta, ground truth and estimates round-trip") {
  TempDir dir;
  DatasetMeta m;
  m.motion = "walk";
  m.frames = 2;
  m.fps = 30;
  m.seed = 18446744073709551615ull;
  m.start_utime = 1'700'000'000'000'000;
  m.stature_mm = 1834.5;
  m.camera_ids = {0, 1, 2};
  m.noise = "salt_pepper=0.01";
  write_meta(dir.path / "meta.json", m);
  const DatasetMeta b = read_meta(dir.path / "meta.json");
  CHECK(b.motion == m.motion);
  CHECK(b.seed == m.seed);
  CHECK(b.start_utime == m.start_utime);
  CHECK(b.camera_ids == m.camera_ids);
  CHECK(b.stature_mm == m.stature_mm);

  write_ground_truth(dir.path / "gt.csv", {record(0, 1.5), record(1, 2.5)});
  const auto gt = read_ground_truth(dir.path / "gt.csv");
  REQUIRE(gt.size() == 2);
  CHECK(gt[1].utime == record(1, 2.5).utime);
  CHECK(gt[1].joints[24].z() == 1024.125);

  {
    EstimateWriter w(dir.path / "est.csv");
    PoseRecord r = record(5, 0);
    r.valid = false;
    r.reason = 4;
    w.write(r);
  }
  const auto est = read_estimates(dir.path / "est.csv");
  REQUIRE(est.size() == 1);
  CHECK_FALSE(est[0].valid);
  CHECK(est[0].reason == 4);
}

TEST_CASE("bad meta.json fields are errors naming the file and the field, never an abort") {
  TempDir dir;
  const fs::path file = dir.path / "meta.json";
  const auto error_of = [&](const std::string& text) -> std::string {
    std::ofstream(file) << text;
    try {
      read_meta(file);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  const std::string good =
      R"({"format": 1, "motion": "walk", "frames": 3, "fps": 30, "seed": 7, "start_utime": 1700000000000000,)"
      R"( "stature_mm": 1750, "noise": "", "camera_ids": [0, 1]})";
  CHECK(error_of(good).empty());
  // Datasets written before 64-bit numbers: seed and start_utime as strings of digits.
  CHECK(
      error_of(
          R"({"format": 1, "motion": "walk", "frames": 3, "fps": 30, "seed": "7", "start_utime": "17",)"
          R"( "stature_mm": 1750, "noise": "", "camera_ids": [0]})")
          .empty());
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    t.replace(t.find(from), from.size(), to);
    return error_of(t);
  };
  CHECK_THAT(with(R"("seed": 7)", R"("seed": "abc")"),
             Catch::Contains("meta.json") && Catch::Contains("field 'seed'"));
  CHECK_THAT(with(R"("seed": 7)", R"("seed": -1)"), Catch::Contains("field 'seed'"));
  CHECK_THAT(with(R"("frames": 3)", R"("frames": "x")"), Catch::Contains("field 'frames'"));
  CHECK_THAT(with(R"("fps": 30)", R"("fps": 0)"), Catch::Contains("field 'fps' must be positive"));
  CHECK_THAT(with(R"("motion": "walk", )", ""), Catch::Contains("missing field 'motion'"));
  CHECK_THAT(with(R"([0, 1])", R"([0, "one"])"), Catch::Contains("field 'camera_ids'"));
  CHECK_THAT(error_of("{not json"), Catch::Contains("meta.json: not valid JSON"));
}

TEST_CASE("bad pose files name the file, line and column") {
  TempDir dir;
  write_ground_truth(dir.path / "gt.csv", {record(0, 1), record(1, 2)});
  std::ifstream in(dir.path / "gt.csv");
  std::string header, l1, l2;
  std::getline(in, header);
  std::getline(in, l1);
  std::getline(in, l2);
  auto expect_error = [&](const std::string& text, const std::string& needle) {
    std::ofstream(dir.path / "bad.csv") << text;
    CHECK_THROWS_WITH(read_ground_truth(dir.path / "bad.csv"),
                      Catch::Contains("bad.csv") && Catch::Contains(needle));
  };
  expect_error(header + "\n" + l1 + "\n" + l2.substr(0, l2.size() / 2) + "\n", ":3: expected");
  expect_error(header + "\n" + l1 + ",7\n", ":2: expected");
  expect_error("frame,time\n", ":1: header");
  std::string nan_line = l1;
  nan_line.replace(nan_line.rfind(',') + 1, std::string::npos, "nan");
  expect_error(header + "\n" + nan_line + "\n", "RToe");
  expect_error(header + "\n" + l2 + "\n" + l1 + "\n", "not after frame");
  CHECK_THROWS_WITH(read_estimates(dir.path / "none.csv"), Catch::Contains("cannot open"));
}
