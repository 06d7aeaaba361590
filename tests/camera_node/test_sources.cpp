#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "hullpose/camera_node/frame_source.hpp"
#include "hullpose/common/check.hpp"
#include "test_dataset.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;
namespace fs = std::filesystem;

namespace {

SourceContext context(int w, int h, const fs::path& base = {}) {
  SourceContext c;
  c.camera_id = 2;
  c.camera.id = 2;
  c.camera.width = w;
  c.camera.height = h;
  c.base_dir = base;
  return c;
}

fs::path sequence_dir() {
  static const test::ScratchDataset d("hullpose_test_sources", test::small_synth({64, 48}, 3, 1, 1),
                                      2);
  return d.dir.path;
}

}  // namespace

TEST_CASE("the registry knows the built-in backends and names unknown ones") {
  const auto names = SourceRegistry::builtin().names();
  CHECK(std::find(names.begin(), names.end(), "libcamera") != names.end());
  CHECK(std::find(names.begin(), names.end(), "v4l2") != names.end());
  CHECK(std::find(names.begin(), names.end(), "file") != names.end());
  CHECK_THROWS_WITH(
      SourceRegistry::builtin().create("gige", Params("cam.yaml: source"), context(64, 48)),
      Catch::Contains(
          "cam.yaml: source.type: unknown source 'gige' (known: libcamera, v4l2, file"));
  Params typo("cam.yaml: source");
  typo.set("path", "x_%d.png");
  typo.set("fsp", "30");
  CHECK_THROWS_WITH(SourceRegistry::builtin().create("file", typo, context(64, 48)),
                    Catch::Contains("cam.yaml: source: unknown parameter(s): fsp"));
}

TEST_CASE("file source replays an image sequence with counters and timestamps") {
  const fs::path dir = sequence_dir();
  Params p("source");
  p.set("path", "cam2/rgb_%06d.png");
  p.set("fps", "20");
  p.set("start_utime", "1000000");
  auto src = SourceRegistry::builtin().create("file", p, context(64, 48, dir));
  src->start();
  Frame f;
  for (int i = 0; i < 3; ++i) {
    REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);
    CHECK(f.sequence == i);
    CHECK(f.capture_utime == 1000000 + i * 50000);
    const cv::Mat expected = cv::imread(test::indexed(dir / "cam2", "rgb", i));
    CHECK(cv::norm(f.image, expected, cv::NORM_INF) == 0);
  }
  CHECK(src->grab(f, 0) == GrabStatus::kEndOfStream);
  src->stop();

  p.set("loop", "true");
  p.set("preload", "true");
  auto looping = SourceRegistry::builtin().create("file", p, context(64, 48, dir));
  looping->start();
  for (int i = 0; i < 7; ++i) REQUIRE(looping->grab(f, 0) == GrabStatus::kFrame);
  CHECK(f.sequence == 6);
  CHECK(cv::norm(f.image, cv::imread(test::indexed(dir / "cam2", "rgb", 0)), cv::NORM_INF) == 0);
}

TEST_CASE("a triggered file source shows the frame of the trigger's sequence") {
  const fs::path dir = sequence_dir();  // 3 frames
  Params p("source");
  p.set("path", "cam2/rgb_%06d.png");
  auto src = SourceRegistry::builtin().create("file", p, context(64, 48, dir));
  REQUIRE(src->triggerable());
  src->start();
  Frame f;
  const auto shows = [&](int k) {
    return cv::norm(f.image, cv::imread(test::indexed(dir / "cam2", "rgb", k)), cv::NORM_INF) == 0;
  };
  src->expose(2, 777);
  REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);
  CHECK(shows(2));
  CHECK(f.capture_utime == 777);
  src->prepare(1);  // decoded ahead, then handed out at the trigger
  src->expose(1, 888);
  REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);
  CHECK(shows(1));
  CHECK(f.capture_utime == 888);
  src->prepare(0);  // a different trigger came: the prepared frame is not used
  src->expose(2, 999);
  REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);
  CHECK(shows(2));
  src->expose(3, 1000);  // past the recording
  CHECK(src->grab(f, 0) == GrabStatus::kEndOfStream);

  p.set("loop", "true");
  auto looping = SourceRegistry::builtin().create("file", p, context(64, 48, dir));
  looping->start();
  looping->expose(7, 1);
  REQUIRE(looping->grab(f, 0) == GrabStatus::kFrame);
  CHECK(shows(1));
}

TEST_CASE("file source errors name the camera and the file") {
  const fs::path dir = sequence_dir();
  Params missing("source");
  missing.set("path", "cam2/none_%06d.png");
  auto src = SourceRegistry::builtin().create("file", missing, context(64, 48, dir));
  CHECK_THROWS_WITH(src->start(), Catch::Contains("camera 2: file source: first image") &&
                                      Catch::Contains("none_000000.png not found"));

  Params wrong_size("source");
  wrong_size.set("path", "cam2/rgb_%06d.png");
  auto big = SourceRegistry::builtin().create("file", wrong_size, context(640, 480, dir));
  big->start();
  Frame f;
  CHECK_THROWS_WITH(big->grab(f, 0), Catch::Contains("is 64x48, the rig camera is 640x480"));

  Params hostile("source");
  hostile.set("path", "cam2/%s%n.png");
  CHECK_THROWS_WITH(SourceRegistry::builtin().create("file", hostile, context(64, 48, dir)),
                    Catch::Contains("must contain exactly one %d or %0Nd"));
}

TEST_CASE("a missing V4L2 device gives an error naming the device and what was tried") {
  Params p("source");
  p.set("device", "/dev/video-hullpose-absent");
  auto src = SourceRegistry::builtin().create("v4l2", p, context(640, 480));
  CHECK_THROWS_WITH(
      src->start(),
      Catch::Contains("camera 2: v4l2 device /dev/video-hullpose-absent: cannot open") &&
          Catch::Contains("tried open(2)"));
  src->stop();  // harmless after a failed start
  Params bad("source");
  bad.set("pixel_format", "H264");
  CHECK_THROWS_WITH(SourceRegistry::builtin().create("v4l2", bad, context(640, 480)),
                    Catch::Contains("source.pixel_format: unsupported pixel format 'H264'"));
}

TEST_CASE("a missing libcamera camera gives an error naming the camera and what was listed") {
  Params p("source");
  p.set("camera", "/base/soc/i2c0mux/i2c@1/imx296@1a");
  p.set("exposure_us", "3000");
  auto src = SourceRegistry::builtin().create("libcamera", p, context(640, 480));
  CHECK_THROWS_WITH(src->start(), Catch::Contains("camera 2: libcamera") &&
                                      Catch::Contains("/base/soc/i2c0mux/i2c@1/imx296@1a") &&
                                      Catch::Contains("CameraManager listed"));
  Params bad("source");
  bad.set("exposure_us", "50000");
  bad.set("frame_duration_us", "33333");
  CHECK_THROWS_WITH(SourceRegistry::builtin().create("libcamera", bad, context(640, 480)),
                    Catch::Contains("source.exposure_us: 50000 exceeds frame_duration_us 33333"));
}

TEST_CASE(
    "file source plays video files frame-exactly on triggers; corrupt frames are reported, not "
    "thrown") {
  const test::ScratchDir scratch("hullpose_test_video");
  const fs::path& dir = scratch.path;
  fs::create_directories(dir);
  // 12 frames whose grey level encodes the index, MJPG in AVI (OpenCV's FFmpeg backend).
  const std::string video = (dir / "clip.avi").string();
  {
    cv::VideoWriter w(video, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25, cv::Size(64, 48));
    REQUIRE(w.isOpened());
    for (int i = 0; i < 12; ++i) w.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(20 * i)));
  }
  Params p("source");
  p.set("path", video);
  auto src = SourceRegistry::builtin().create("file", p, context(64, 48));
  src->start();
  Frame f;
  auto level = [&] { return cv::mean(f.image)[0] / 20; };
  REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);
  CHECK(level() == Approx(0).margin(0.2));
  for (int seq : {7, 8, 3, 11}) {  // forward, next, backward, last
    src->expose(seq, 1000 + seq);
    REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);
    CHECK(level() == Approx(seq).margin(0.2));
    CHECK(f.capture_utime == 1000 + seq);
  }
  CHECK(src->grab(f, 0) == GrabStatus::kEndOfStream);
  src->stop();

  // A truncated video (its index gone) and a damaged one (bytes overwritten mid-file): either the
  // file is refused at start() naming it (exit 2 in the node), or what decodes plays and the rest
  // is corrupt frames or the end, never a throw or a hang.
  fs::copy_file(video, dir / "cut.avi", fs::copy_options::overwrite_existing);
  fs::resize_file(dir / "cut.avi", fs::file_size(video) * 9 / 10);
  fs::copy_file(video, dir / "damaged.avi", fs::copy_options::overwrite_existing);
  {
    std::fstream d(dir / "damaged.avi", std::ios::in | std::ios::out | std::ios::binary);
    d.seekp(static_cast<std::streamoff>(fs::file_size(video) / 2));
    d << std::string(600, '\xff');
  }
  for (const char* name : {"cut.avi", "damaged.avi"}) {
    INFO(name);
    p.set("path", (dir / name).string());
    auto bad = SourceRegistry::builtin().create("file", p, context(64, 48));
    try {
      bad->start();
    } catch (const Error& e) {
      CHECK_THAT(e.what(), Catch::Contains(name));
      continue;
    }
    int frames = 0, corrupt = 0, calls = 0;
    for (GrabStatus s; (s = bad->grab(f, 0)) != GrabStatus::kEndOfStream && calls < 100; ++calls)
      (s == GrabStatus::kFrame ? frames : corrupt) += 1;
    CHECK(calls < 100);
    CHECK(frames + corrupt <= 12);
    CHECK(frames >= 3);
    if (std::string_view(name) == "cut.avi")
      CHECK(corrupt > 0);  // the frames past the cut: 9 + 3 here
  }

  // An image sequence with an undecodable file in the middle: that frame is corrupt, the next
  // plays.
  for (int i = 0; i < 3; ++i)
    cv::imwrite((dir / ("f_" + std::to_string(i) + ".png")).string(),
                cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(20 * i)));
  std::ofstream(dir / "f_1.png", std::ios::trunc) << "not a png";
  p.set("path", (dir / "f_%d.png").string());
  auto seq = SourceRegistry::builtin().create("file", p, context(64, 48));
  seq->start();
  CHECK(seq->grab(f, 0) == GrabStatus::kFrame);
  CHECK(seq->grab(f, 0) == GrabStatus::kCorruptFrame);
  REQUIRE(seq->grab(f, 0) == GrabStatus::kFrame);
  CHECK(level() == Approx(2).margin(0.2));
  CHECK(f.sequence == 2);
  CHECK(seq->grab(f, 0) == GrabStatus::kEndOfStream);
  fs::remove_all(dir);
}
