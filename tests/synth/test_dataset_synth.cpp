#include <unistd.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"
#include "hullpose/synth/dataset_writer.hpp"
#include "hullpose/synth/rig_gen.hpp"

using namespace hullpose;
using namespace hullpose::synth;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag)
      : path(fs::temp_directory_path() /
             ("hullpose-synth-" + tag + "-" + std::to_string(::getpid()))) {
    fs::remove_all(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

// Small images keep the sanitizer run of these tests quick.
constexpr const char* kRig = "ring:cameras=5,width=400,rows=300";

SynthConfig small(const fs::path& out) {
  SynthConfig c;
  c.motion = "walk";
  c.rig = kRig;
  c.out = out;
  c.frames = 3;
  c.seed = 7;
  return c;
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("a dataset round-trips through disk: rig, meta, ground truth, masks, colour frames") {
  TempDir dir("roundtrip");
  SynthConfig cfg = small(dir.path);
  cfg.rgb = true;
  cfg.backgrounds = 2;
  const SynthSummary s = write_dataset(cfg);
  CHECK(s.frames == 3);
  CHECK(s.cameras == 6);

  const DatasetPaths paths(dir.path);
  const Rig rig = load_rig(paths.rig());
  CHECK(rig == rig_from_name_or_file(kRig));
  CHECK_FALSE(fs::exists(dir.path / "rig_true.yaml"));
  const DatasetMeta meta = read_meta(paths.meta());
  CHECK(meta.motion == "walk");
  CHECK(meta.frames == 3);
  CHECK(meta.fps == 30);
  CHECK(meta.seed == 7);
  CHECK(meta.stature_mm == 1750);
  CHECK(meta.noise.empty());
  CHECK(meta.camera_ids == std::vector<int>{0, 1, 2, 3, 4, 5});

  // Ground truth = the motion at the frame times, placed at the capture volume's centre.
  MotionOptions mo;
  mo.centre_mm = Eigen::Vector3d(0, 0, 0);
  const auto motion = make_builtin_motion("walk", mo);
  const auto gt = read_ground_truth(paths.ground_truth());
  REQUIRE(gt.size() == 3);
  BodyShape body;
  std::vector<Primitive> prims;
  std::vector<ViewRenderer> views(rig.cameras.begin(), rig.cameras.end());
  for (int f = 0; f < 3; ++f) {
    JointPositions q;
    motion->sample(f / 30.0, q);
    CHECK(gt[static_cast<size_t>(f)].utime == meta.start_utime + std::llround(f * 1e6 / 30));
    for (int j = 0; j < kNumJoints; ++j)
      CHECK((gt[static_cast<size_t>(f)].joints[static_cast<size_t>(j)] - q[static_cast<size_t>(j)])
                .norm() < 1e-3);
    pose_avatar(body, q, prims);
    for (const auto& cam : rig.cameras) {
      INFO("camera " << cam.id << " frame " << f);
      const cv::Mat mask = cv::imread(paths.mask(cam.id, f).string(), cv::IMREAD_UNCHANGED);
      REQUIRE(mask.type() == CV_8UC1);
      cv::Mat expected;
      views[static_cast<size_t>(cam.id)].render_mask(prims, expected);
      CHECK(cv::countNonZero(mask != expected) == 0);
      CHECK(cv::countNonZero(mask) > 250);
      // The ground-truth pelvis projects into the silhouette.
      const auto px = cam.project(q[index(Joint::LBack)]);
      REQUIRE(px);
      CHECK(mask.at<uint8_t>(cvRound(px->y()), cvRound(px->x())) == 255);
      const cv::Mat rgb = cv::imread(paths.rgb(cam.id, f).string(), cv::IMREAD_UNCHANGED);
      CHECK(rgb.type() == CV_8UC3);
      CHECK(rgb.size() == mask.size());
    }
  }
  for (int k = 0; k < 2; ++k) CHECK(fs::exists(paths.background(3, k)));
  CHECK_FALSE(fs::exists(paths.background(3, 2)));
}

TEST_CASE(
    "faults: dropped frames, a dark camera, calibration error, silhouette noise; all seeded") {
  TempDir a("faults-a"), b("faults-b"), c("faults-c");
  SynthConfig cfg = small(a.path);
  cfg.faults = FaultSpec::parse(
      "drop=0.3,dark=2@1,calib_px=2,calib_deg=0.5,salt=0.001,pepper=0.02,blobs=2,holes=2");
  write_dataset(cfg);
  cfg.out = b.path;
  write_dataset(cfg);  // same seed: identical bytes
  cfg.out = c.path;
  cfg.seed = 8;
  write_dataset(cfg);

  const DatasetPaths pa(a.path), pb(b.path), pc(c.path);
  CHECK(read_meta(pa.meta()).noise == cfg.faults.describe());
  CHECK(FaultSpec::parse(cfg.faults.describe()).describe() == cfg.faults.describe());
  int present = 0, differ = 0;
  for (int cam = 0; cam < 6; ++cam)
    for (int f = 0; f < 3; ++f) {
      const bool dropped = frame_dropped(cfg.faults, 7, cam, f);
      CHECK(fs::exists(pa.mask(cam, f)) == !dropped);
      if (dropped) continue;
      ++present;
      CHECK(file_bytes(pa.mask(cam, f)) == file_bytes(pb.mask(cam, f)));
      if (fs::exists(pc.mask(cam, f)))
        differ += file_bytes(pa.mask(cam, f)) != file_bytes(pc.mask(cam, f));
      if (cam == 2 && f >= 1)
        CHECK(cv::countNonZero(cv::imread(pa.mask(cam, f).string(), cv::IMREAD_GRAYSCALE)) == 0);
    }
  CHECK(present > 6);
  CHECK(present < 18);
  CHECK(differ > 0);

  // The written rig is perturbed; the true rig rendered the masks.
  const Rig truth = load_rig(a.path / "rig_true.yaml"), told = load_rig(pa.rig());
  CHECK(truth == rig_from_name_or_file(kRig));
  for (size_t i = 0; i < truth.cameras.size(); ++i) {
    const auto &t = truth.cameras[i], &w = told.cameras[i];
    CHECK((t.centre() - w.centre()).norm() < 1e-6);  // only orientation and principal point err
    const double deg = Eigen::AngleAxisd(t.R * w.R.transpose()).angle() * 180 / M_PI;
    CHECK(deg > 0);
    CHECK(deg < 4);
    CHECK(std::hypot(t.cx - w.cx, t.cy - w.cy) < 12);
  }
}

TEST_CASE("silhouette noise and trigger jitter behave as specified") {
  FaultSpec f = FaultSpec::parse("salt=0.01");
  cv::Mat mask(600, 800, CV_8UC1, cv::Scalar(0));
  corrupt_silhouette(mask, f, 1, 0, 0);
  CHECK(cv::countNonZero(mask) == Approx(4800).margin(400));
  f = FaultSpec::parse("pepper=0.5");
  mask.setTo(0);
  mask(cv::Rect(100, 100, 100, 100)).setTo(255);
  corrupt_silhouette(mask, f, 1, 0, 0);
  CHECK(cv::countNonZero(mask) == Approx(10000 * std::exp(-0.5)).margin(400));  // with replacement
  f = FaultSpec::parse("jitter_ms=5");
  double sum2 = 0;
  for (int i = 0; i < 2000; ++i) sum2 += std::pow(trigger_offset_s(f, 3, 1, i), 2);
  CHECK(std::sqrt(sum2 / 2000) == Approx(0.005).epsilon(0.1));
  CHECK(trigger_offset_s(f, 3, 1, 5) == trigger_offset_s(f, 3, 1, 5));
  CHECK(trigger_offset_s(f, 3, 1, 5) != trigger_offset_s(f, 3, 2, 5));
  CHECK_THROWS_WITH(FaultSpec::parse("salt=2"), Contains("salt is a probability"));
  CHECK_THROWS_WITH(FaultSpec::parse("sparkle=1"), Contains("unknown key 'sparkle'"));
  CHECK_THROWS_WITH(FaultSpec::parse("blobs"), Contains("not key=value"));
}

TEST_CASE("a BVH clip longer than asked for, and bad requests") {
  TempDir dir("bad");
  SynthConfig cfg = small(dir.path);
  cfg.motion = (fs::path(HULLPOSE_SHARED_DIR) / "data/mocap/07_01.bvh").string();
  cfg.frames = 500;
  CHECK_THROWS_WITH(write_dataset(cfg), Contains("07_01.bvh has 79 frames at 30 fps"));
  cfg.motion = "walk";
  cfg.rig = "/nonexistent/rig.yaml";
  CHECK_THROWS_WITH(write_dataset(cfg), Contains("rig file not found"));
  cfg.rig = "thesis8";
  cfg.out = "/proc/hullpose-cannot-write-here";
  CHECK_THROWS_WITH(write_dataset(cfg), Contains("cannot create the dataset directory"));
}
