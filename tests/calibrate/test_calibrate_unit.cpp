// Fast pieces of the calibration tool (also run under the sanitizers): Jacobians, the folder
// provider, the command line, refusing a symmetric board, hand-marked corners.
#include <Eigen/Geometry>
#include <array>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "hullpose/calibrate/bundle_adjust.hpp"
#include "hullpose/calibrate/options.hpp"
#include "hullpose/calibrate/rig_calibrator.hpp"
#include "hullpose/common/check.hpp"
#include "synthetic_capture.hpp"

using namespace hullpose;
using namespace hullpose::calibrate;
using namespace hullpose::calibrate::testing;
using Catch::Matchers::Contains;

namespace {

const BoardSpec kBoard{9, 6, 120};

}  // namespace

TEST_CASE("analytic Jacobians match central differences") {
  const Rig rig = make_ring_rig(1);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const auto& cam : rig.cameras) {
    const Eigen::Isometry3d board = floor_board_pose(kBoard);
    for (int k = 0; k < kBoard.corner_count(); k += 7) {
      const Eigen::Vector3d X = kBoard.corner_mm(k);
      Eigen::Vector2d px;
      CameraJacobian jc;
      BoardJacobian jb;
      REQUIRE(project_with_jacobians(cam, board, X, px, &jc, &jb));
      for (int i = 0; i < kCameraParams; ++i) {
        const double h = i < 3 ? 1e-7 : (i < 6 ? 1e-4 : (i < 10 ? 1e-4 : 1e-7));
        Eigen::Matrix<double, kCameraParams, 1> step =
            Eigen::Matrix<double, kCameraParams, 1>::Zero();
        step(i) = h;
        CameraModel plus = cam, minus = cam;
        apply_camera_step(plus, step);
        apply_camera_step(minus, -step);
        Eigen::Vector2d pp, pm;
        project_with_jacobians(plus, board, X, pp, nullptr, nullptr);
        project_with_jacobians(minus, board, X, pm, nullptr, nullptr);
        const Eigen::Vector2d numeric = (pp - pm) / (2 * h);
        INFO("camera " << cam.id << " parameter " << i);
        CHECK((numeric - jc.col(i)).norm() < 1e-4 * std::max(1.0, numeric.norm()));
      }
      for (int i = 0; i < 6; ++i) {
        const double h = i < 3 ? 1e-7 : 1e-4;
        Eigen::Matrix<double, 6, 1> step = Eigen::Matrix<double, 6, 1>::Zero();
        step(i) = h;
        Eigen::Isometry3d plus = board, minus = board;
        apply_board_step(plus, step);
        apply_board_step(minus, -step);
        Eigen::Vector2d pp, pm;
        project_with_jacobians(cam, plus, X, pp, nullptr, nullptr);
        project_with_jacobians(cam, minus, X, pm, nullptr, nullptr);
        const Eigen::Vector2d numeric = (pp - pm) / (2 * h);
        INFO("camera " << cam.id << " board parameter " << i);
        CHECK((numeric - jb.col(i)).norm() < 1e-4 * std::max(1.0, numeric.norm()));
      }
    }
  }
}

TEST_CASE("folder provider groups images by name across cam folders") {
  const auto dir = std::filesystem::temp_directory_path() / "hullpose_calib_folder_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "cam0");
  std::filesystem::create_directories(dir / "cam3");
  std::filesystem::create_directories(dir / "notes");
  const cv::Mat img(60, 80, CV_8UC1, cv::Scalar(100));
  cv::imwrite((dir / "cam0" / "floor.png").string(), img);
  cv::imwrite((dir / "cam3" / "floor.png").string(), img);
  cv::imwrite((dir / "cam3" / "v001.png").string(), img);
  FolderViewProvider provider(dir);
  CHECK(provider.camera_ids() == std::vector<int>{0, 3});
  CaptureInstant instant;
  REQUIRE(provider.next(instant));
  CHECK(instant.name == "floor");
  CHECK(instant.images.size() == 2);
  REQUIRE(provider.next(instant));
  CHECK(instant.name == "v001");
  REQUIRE(instant.images.size() == 1);
  CHECK(instant.images[0].camera_id == 3);
  CHECK_FALSE(provider.next(instant));
  std::filesystem::remove_all(dir);
  CHECK_THROWS_WITH(FolderViewProvider(dir), Contains("not a directory"));
}

TEST_CASE("command line errors name the argument") {
  auto parse = [](std::initializer_list<const char*> args) {
    std::array<const char*, 32> argv{"hullpose-calibrate"};
    std::copy(args.begin(), args.end(), argv.begin() + 1);
    return parse_command_line(static_cast<int>(args.size() + 1), argv.data()).value();
  };
  CHECK_THROWS_WITH(
      parse({"--images", "d", "--out", "r.yaml", "--board", "9by6", "--square-mm", "100"}),
      Contains("--board: '9by6' must be COLSxROWS"));
  CHECK_THROWS_WITH(
      parse({"--images", "d", "--out", "r.yaml", "--board", "9x6", "--square-mm", "ten"}),
      Contains("--square-mm: 'ten' is not a number"));
  CHECK_THROWS_WITH(parse({"--images", "d", "--board", "9x6", "--square-mm", "100"}),
                    Contains("--out"));
  CHECK_THROWS_WITH(parse({"--frobnicate"}), Contains("unknown option '--frobnicate'"));
  const CommandLine ok = parse({"--images", "d", "--out", "r.yaml", "--board", "9x6", "--square-mm",
                                "120", "--floor-view", "ground", "--no-k3"});
  CHECK(ok.options.board.square_mm == 120);
  CHECK(ok.options.floor_views == std::vector<std::string>{"ground"});
  CHECK(parse({"--images", "d", "--out", "r.yaml", "--board", "9x6", "--square-mm", "120"})
            .options.floor_views == std::vector<std::string>{"floor"});
  CHECK(parse({"--images", "d", "--out", "r.yaml", "--board", "9x6", "--square-mm", "120",
               "--floor-view", "f1", "--floor-view", "f2"})
            .options.floor_views == std::vector<std::string>{"f1", "f2"});
  CHECK_FALSE(ok.options.intrinsics.estimate_k3);
}
TEST_CASE("floor views must be named, once each") {
  CalibrationOptions o;
  o.board = {9, 6, 120};
  o.floor_views = {};
  CHECK_THROWS_WITH(RigCalibrator(o), Contains("name at least one floor view"));
  o.floor_views = {"floor", "floor2", "floor"};
  CHECK_THROWS_WITH(RigCalibrator(o), Contains("floor view 'floor' is named twice"));
}
TEST_CASE("a symmetric board is refused unless its corners are marked") {
  CalibrationOptions o;
  o.board = {8, 6, 120};
  CHECK_THROWS_WITH(RigCalibrator(o), Contains("symmetric under a half turn"));
  o.board.corners_marked = true;
  CHECK_NOTHROW(RigCalibrator(o));
  // Found or not, a detector's order of a symmetric board would be a guess.
  CHECK(detect_board(cv::Mat(486, 644, CV_8UC1, cv::Scalar(128)), o.board).empty());
}

// The Utrecht case in miniature: a symmetric board the detector does not search, four corners
// marked a pixel or two off, every corner refined to the rendered truth.
TEST_CASE("four marked corners give every corner of the board; marks that outline nothing fail") {
  const Rig rig = make_ring_rig(2);
  BoardSpec board{8, 6, 120};
  board.corners_marked = true;
  const BoardRenderer renderer(rig, board, 0.0, 2.0);
  std::mt19937 rng(5);
  cv::Mat image;
  std::vector<cv::Point2f> truth;
  for (const PlannedView& v : make_capture_plan(rig, board, {}, 3)) {
    image = renderer.render(0, v.world_from_board, rng);
    if (image.empty()) continue;
    truth = project_board(rig.cameras[0], board, v.world_from_board, 0.0, rng);
    break;
  }
  REQUIRE(!image.empty());
  REQUIRE(truth.size() == 48u);
  const MarkedCorners marks = {
      truth[0] + cv::Point2f(1.5f, -1.0f), truth[7] + cv::Point2f(-1.0f, 1.5f),
      truth[47] + cv::Point2f(1.0f, 1.0f), truth[40] + cv::Point2f(-1.5f, -1.5f)};
  const std::vector<cv::Point2f> corners = corners_from_marks(image, board, marks);
  REQUIRE(corners.size() == truth.size());
  double worst = 0;
  for (size_t k = 0; k < truth.size(); ++k)
    worst = std::max(worst, cv::norm(corners[k] - truth[k]));
  CHECK(worst < 0.3);

  const MarkedCorners crossed = {marks[0], marks[2], marks[1], marks[3]};
  CHECK_THROWS_WITH(corners_from_marks(image, board, crossed), Contains("convex quadrilateral"));
  MarkedCorners outside = marks;
  outside[2] = {static_cast<float>(image.cols) + 3, 10};
  CHECK_THROWS_WITH(corners_from_marks(image, board, outside), Contains("outside the"));
  // Marks around noise: the refined corners scatter off their rows and columns.
  cv::Mat noise(image.size(), CV_8UC1);
  cv::RNG(7).fill(noise, cv::RNG::NORMAL, 128, 40);
  CHECK_THROWS_WITH(corners_from_marks(noise, board, marks), Contains("do not outline the board"));
}

TEST_CASE("--corners reads marks by camera and view; bad files name the file and field") {
  const auto dir = std::filesystem::temp_directory_path() / "hullpose-calibrate-marks";
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) {
    const auto p = dir / name;
    std::ofstream(p) << text;
    return p.string();
  };
  auto parse = [](const std::string& file) {
    std::array<const char*, 12> argv{
        "hullpose-calibrate", "--images", "d",         "--out",     "r.yaml", "--board", "8x6",
        "--square-mm",        "115",      "--corners", file.c_str()};
    return parse_command_line(11, argv.data()).value();
  };
  const CommandLine ok = parse(write(
      "ok.yaml", "marks:\n  - {camera: 2, view: floor, corners: [1, 2, 30, 2, 30, 20, 1, 20]}\n"));
  CHECK(ok.options.board.corners_marked);
  REQUIRE(ok.options.marked_corners.count({2, "floor"}) == 1);
  CHECK(ok.options.marked_corners.at({2, "floor"})[2] == cv::Point2f(30, 20));
  const std::string short_list = write(
      "short.yaml", "marks:\n  - {camera: 2, view: floor, corners: [1, 2, 30, 2, 30, 20, 1]}\n");
  CHECK_THROWS_WITH(parse(short_list), Contains("short.yaml:2") && Contains("corners"));
  const std::string twice =
      write("twice.yaml",
            "marks:\n  - {camera: 2, view: f, corners: [1, 2, 3, 4, 5, 6, 7, 8]}\n"
            "  - {camera: 2, view: f, corners: [1, 2, 3, 4, 5, 6, 7, 8]}\n");
  CHECK_THROWS_WITH(parse(twice), Contains("marked twice"));
  // Marks for an image that never came are an error, not silently unused.
  CalibrationOptions o = ok.options;
  RigCalibrator calibrator(o);
  calibrator.add_detection("floor", 1, {644, 486}, {});
  CHECK_THROWS_WITH(calibrator.solve(), Contains("camera 2, view floor, but no such image"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("a miss says what was searched for, and how") {
  const cv::Mat blank(486, 644, CV_8UC1, cv::Scalar(128));
  BoardSpec board = kBoard;
  CHECK(detect_board(blank, board).empty());
  const std::string fast = board_search_summary(board, blank.size());
  CHECK_THAT(fast, Contains("9x6 inner corners"));
  CHECK_THAT(fast, Contains("at double size"));
  CHECK_THAT(fast, Contains("--exhaustive-search"));
  board.exhaustive_search = true;
  CHECK(detect_board(blank, board).empty());
  CHECK_THAT(board_search_summary(board, blank.size()), Contains("exhaustively"));
  // Large images get neither the double-size nor the exhaustive search.
  CHECK_THAT(board_search_summary(board, {1600, 1200}), !Contains("double"));
}
