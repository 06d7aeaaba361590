// Carving: the hierarchical fast path equals the brute-force reference voxel for voxel; k-of-n
// tolerance, missing and malformed views.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "hullpose/carve/carver.hpp"
#include "hullpose/carve/column_counts.hpp"
#include "support/carve_helpers.hpp"
#include "support/synthetic_scene.hpp"
#include "support/test_sizes.hpp"

using namespace hullpose;
using fusion::BitGrid;
namespace ft = hullpose::fusion::testing;
using ft::brute;
using ft::fast;

TEST_CASE("VoxelProjector is CameraModel::project rounded to the nearest pixel") {
  const Rig rig = ft::thesis_like_rig();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1200, 1200), h(0, 2200);
  for (const CameraModel& cam : rig.cameras) {
    const carve::VoxelProjector p(cam);
    for (int i = 0; i < 300; ++i) {
      // z first: the order x86-64 GCC evaluated one call's arguments in (unspecified in C++).
      const double z = h(rng), y = u(rng), x = u(rng);
      const Eigen::Vector3d w(x, y, z);
      const auto ref = cam.project(w);
      int px = -1, py = -1;
      const bool in = p.pixel(w, px, py);
      REQUIRE(ref.has_value());
      const bool ref_in = ref->x() >= -0.5 && ref->y() >= -0.5 && ref->x() < cam.width - 0.5 &&
                          ref->y() < cam.height - 0.5;
      REQUIRE(in == ref_in);
      if (in) {
        CHECK(px == static_cast<int>(std::floor(ref->x() + 0.5)));
        CHECK(py == static_cast<int>(std::floor(ref->y() + 0.5)));
      }
    }
  }
}

TEST_CASE("fast carving equals brute force at 64³ (32³ under the sanitizers)") {
  const Rig rig = ft::thesis_like_rig(320, 240);
  for (int k : {0, 1}) {
    carve::Carver carver(rig, {ft::kUnitResolution, k, 2});
    INFO("k " << k);
    const auto views = ft::render_views(rig, ft::human_capsules(0.6, 1.8, {120, -100}));
    carve::CarveReport report;
    const BitGrid a = fast(carver, views, &report);
    CHECK(report.valid);
    CHECK(report.cameras_used == 8);
    CHECK(report.voxels == a.count());
    CHECK(a.count() > 500 / ft::kVoxelScale);
    CHECK(a == brute(carver, views));
  }
}

TEST_CASE("the hull contains the body") {
  const Rig rig = ft::thesis_like_rig(400, 300);
  carve::Carver carver(rig, {ft::kUnitResolution, 0, 1});
  const auto body = ft::human_capsules(0.25, 0.4);
  const BitGrid hull = fast(carver, ft::render_views(rig, body));
  const BitGrid solid = ft::voxelise(carver.grid(), body);
  size_t inside = 0;
  solid.for_each([&](int x, int y, int z) { inside += hull.get(x, y, z); });
  CHECK(inside >= solid.count() * 95 / 100);
  CHECK(hull.count() < solid.count() * 4);
}

TEST_CASE("k-of-n tolerance: a dark camera and a noisy one") {
  const Rig rig = ft::thesis_like_rig(320, 240);
  const auto views = ft::render_views(rig, ft::human_capsules(0.5));
  carve::Carver strict(rig, {ft::kUnitResolution, 0, 1});
  carve::Carver tolerant(rig, {ft::kUnitResolution, 1, 1});
  const BitGrid clean = fast(strict, views);

  SECTION("dark camera: all-but-one equals carving without that camera") {
    auto dark = views;
    dark[3] = cv::Mat::zeros(dark[3].size(), CV_8UC1);
    CHECK(fast(strict, dark).count() == 0);
    auto absent = views;
    absent[3] = cv::Mat();
    carve::CarveReport report;
    const BitGrid without = fast(strict, absent, &report);
    CHECK(report.missing_cameras == std::vector<int>{3});
    CHECK(report.cameras_used == 7);
    const BitGrid tol = fast(tolerant, dark);
    CHECK(tol == without);
    CHECK(tol == brute(tolerant, dark));
  }
  SECTION("noisy camera: holes and speckle lose the limb at k = 0, not at k = 1") {
    auto noisy = views;
    cv::Mat& m = noisy[2];
    std::mt19937 rng(4);
    std::uniform_int_distribution<int> px(0, m.cols - 1), py(0, m.rows - 1);
    for (int i = 0; i < 3000; ++i) {
      const int col = px(rng), row = py(rng);  // column first: see the projector test
      m.at<uint8_t>(row, col) = static_cast<uint8_t>(i % 2 ? 255 : 0);
    }
    cv::rectangle(m, cv::Rect(0, m.rows / 2, m.cols, m.rows / 6), cv::Scalar(0),
                  -1);  // a band of missed pixels
    const BitGrid lost = fast(strict, noisy);
    const BitGrid kept = fast(tolerant, noisy);
    CHECK(lost.count() < clean.count());
    // Every voxel of the clean hull misses at most the noisy camera: kept with k = 1.
    size_t missing = 0;
    clean.for_each([&](int x, int y, int z) { missing += !kept.get(x, y, z); });
    CHECK(missing == 0);
    CHECK(kept == brute(tolerant, noisy));
    CHECK(lost == brute(strict, noisy));
  }
}

TEST_CASE("missing, malformed and too few views are reported, never fused") {
  const Rig rig = ft::thesis_like_rig(160, 120);
  carve::Carver carver(rig, {ft::kUnitResolution, 1, 1});
  auto views = ft::render_views(rig, ft::human_capsules(0.1));
  views[0] = cv::Mat();
  views[5] = cv::Mat::zeros(10, 10, CV_8UC1);
  views[6].convertTo(views[6], CV_16U);
  carve::CarveReport report;
  const BitGrid a = fast(carver, views, &report);
  CHECK(report.valid);
  CHECK(report.cameras_used == 5);
  CHECK(report.missing_cameras == std::vector<int>{0});
  CHECK(report.rejected_cameras == std::vector<int>{5, 6});
  CHECK(a == brute(carver, views));

  std::vector<cv::Mat> one(8);
  one[2] = views[2];
  fast(carver, one, &report);
  CHECK_FALSE(report.valid);  // one camera with k = 1: every voxel would be kept
  CHECK(report.voxels == 0);

  CHECK_THROWS(carver.carve(std::vector<cv::Mat>(3), *std::make_unique<BitGrid>(), report));
  CHECK_THROWS(carve::Carver(rig, {64, 8, 1}));
  CHECK_THROWS(carve::Carver(rig, {4, 0, 1}));
}

TEST_CASE("ColumnCounts decides rectangles like counting their pixels") {
  // Blobs of foreground with values other than 255 too (any non-zero byte is foreground), boxes
  // that reach the image's right edge (the vector loads' tail) and rectangles that leave the box,
  // the image, or span more than 255 rows (where the counts wrap).
  std::mt19937 rng(7);
  carve::ColumnCounts counts;
  counts.reserve(97, 300);
  for (int round = 0; round < 40; ++round) {
    cv::Mat mask(300, 97, CV_8UC1, cv::Scalar(0));
    std::uniform_int_distribution<int> x(0, 96), y(0, 299), r(2, 40), v(1, 255);
    for (int b = 0; b < 6; ++b) {
      // Last argument first, as x86-64 GCC evaluated them (see the projector test).
      const int value = v(rng), radius = r(rng), cx = x(rng), cy = y(rng);
      cv::circle(mask, {cx, cy}, radius, cv::Scalar(value), cv::FILLED);
    }
    if (round % 4 == 0) mask(cv::Rect(10, 5, 60, 290)).setTo(200);  // tall all-foreground areas
    // Pixels outside the box must count as background even where the mask holds foreground.
    cv::Rect box(0, 0, 97, 300);
    if (round % 3 != 0) {
      const int right = x(rng), top = y(rng), left = x(rng);  // last argument first, as above
      box = cv::Rect(left / 2, top / 2, 97 - right / 2, 150);
    }
    const cv::Rect in_image = box & cv::Rect(0, 0, mask.cols, mask.rows);
    counts.build(mask, in_image);
    std::uniform_int_distribution<int> rx(-20, 116), ry(-20, 319);
    for (int q = 0; q < 400; ++q) {
      int x0 = rx(rng), x1 = rx(rng), y0 = ry(rng), y1 = ry(rng);
      if (q % 5 == 0) {  // small rectangles, like the octree's finest nodes
        x1 = x0 + q % 17;
        y1 = y0 + q % 13;
      }
      if (x0 > x1) std::swap(x0, x1);
      if (y0 > y1) std::swap(y0, y1);
      long fg = 0;
      for (int yy = y0; yy <= y1; ++yy)
        for (int xx = x0; xx <= x1; ++xx)
          fg += in_image.contains({xx, yy}) && mask.at<uint8_t>(yy, xx) != 0;
      const long area = long{x1 - x0 + 1} * (y1 - y0 + 1);
      const auto truth = fg == 0      ? carve::Coverage::kNone
                         : fg == area ? carve::Coverage::kAll
                                      : carve::Coverage::kSome;
      const auto got = counts.cover(x0, y0, x1, y1);
      INFO("round " << round << " box " << in_image << " rectangle [" << x0 << ", " << x1 << "] x ["
                    << y0 << ", " << y1 << "]: " << fg << " of " << area);
      if (y1 - y0 + 1 > 255 && truth == carve::Coverage::kAll)
        CHECK(got == carve::Coverage::kSome);  // documented: conservative over 255 rows
      else
        CHECK(got == truth);
    }
  }
}

TEST_CASE("ColumnCounts: where the counts wrap, and an empty box") {
  cv::Mat mask(300, 40, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(0, 0, 20, 300)).setTo(255);
  carve::ColumnCounts counts;
  counts.reserve(mask.cols, mask.rows);
  counts.build(mask, cv::Rect(0, 0, 40, 300));
  CHECK(counts.cover(0, 0, 19, 254) == carve::Coverage::kAll);   // 255 rows: exact
  CHECK(counts.cover(0, 0, 19, 255) == carve::Coverage::kSome);  // 256 rows: 256 = 0 mod 256
  CHECK(counts.cover(0, 0, 19, 299) == carve::Coverage::kSome);
  CHECK(counts.cover(20, 0, 39, 299) == carve::Coverage::kNone);
  CHECK(counts.cover(15, 0, 25, 299) == carve::Coverage::kSome);
  counts.build(mask, cv::Rect(5, 5, 0, 0));  // no foreground box: everything is background
  CHECK(counts.cover(0, 0, 39, 299) == carve::Coverage::kNone);
  CHECK(counts.cover(3, 3, 3, 3) == carve::Coverage::kNone);
}
