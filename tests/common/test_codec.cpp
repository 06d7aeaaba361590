#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "hullpose/common/silhouette_codec.hpp"

using namespace hullpose;

namespace {

cv::Mat roundtrip(const cv::Mat& mask, PixelRoi* roi = nullptr, size_t* bytes = nullptr) {
  SilhouetteEncoder enc;
  std::vector<uint8_t> payload;
  const PixelRoi r = enc.encode(mask, payload);
  if (roi) *roi = r;
  if (bytes) *bytes = payload.size();
  cv::Mat out;
  SilhouetteHeader h;
  REQUIRE(decode_silhouette(payload, {}, out, &h) == CodecError::kNone);
  CHECK(h.roi == r);
  return out;
}

bool same_mask(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat na = a != 0, nb = b != 0;
  return a.size() == b.size() && cv::countNonZero(na != nb) == 0;
}

cv::Mat human_shape(int w, int h) {
  cv::Mat m(h, w, CV_8UC1, cv::Scalar(0));
  const cv::Scalar fg(255);
  cv::circle(m, {w / 2, h / 5}, h / 16, fg, -1);                                // head
  cv::ellipse(m, {w / 2, h / 2 - h / 12}, {w / 18, h / 6}, 0, 0, 360, fg, -1);  // torso
  cv::line(m, {w / 2, h / 3}, {w / 2 - w / 6, h / 2}, fg, w / 60);              // arms
  cv::line(m, {w / 2, h / 3}, {w / 2 + w / 7, h / 4}, fg, w / 60);
  cv::line(m, {w / 2 - 10, h / 2 + h / 12}, {w / 2 - w / 14, h - h / 12}, fg, w / 45);  // legs
  cv::line(m, {w / 2 + 10, h / 2 + h / 12}, {w / 2 + w / 20, h - h / 12}, fg, w / 45);
  return m;
}

}  // namespace

TEST_CASE("codec round-trips masks of every kind") {
  std::mt19937 rng(7);
  SECTION("empty") {
    cv::Mat m(600, 800, CV_8UC1, cv::Scalar(0));
    PixelRoi roi;
    size_t bytes = 0;
    CHECK(same_mask(roundtrip(m, &roi, &bytes), m));
    CHECK(roi == PixelRoi{});
    CHECK(bytes == 20);
  }
  SECTION("full") {
    cv::Mat m(600, 800, CV_8UC1, cv::Scalar(255));
    PixelRoi roi;
    CHECK(same_mask(roundtrip(m, &roi), m));
    CHECK(roi == PixelRoi{0, 0, 800, 600});
  }
  SECTION("a vertical line one pixel wide: consecutive rows join into one run") {
    // fuzz_silhouette_decoder found it: one run per row, with empty background runs between
    // them, was more runs than a decoder accepts for the ROI's area.
    cv::Mat m(40, 50, CV_8UC1, cv::Scalar(0));
    m(cv::Rect(24, 20, 1, 13)).setTo(255);
    PixelRoi roi;
    size_t bytes = 0;
    CHECK(same_mask(roundtrip(m, &roi, &bytes), m));
    CHECK(roi == PixelRoi{24, 20, 1, 13});
    CHECK(bytes == 20 + 3);  // runs 0, 13, 0
  }
  SECTION("one pixel, at corners and inside") {
    for (cv::Point p : {cv::Point{0, 0}, cv::Point{799, 599}, cv::Point{799, 0}, cv::Point{0, 599},
                        cv::Point{123, 456}}) {
      cv::Mat m(600, 800, CV_8UC1, cv::Scalar(0));
      m.at<uint8_t>(p) = 1;  // any non-zero value is foreground
      PixelRoi roi;
      CHECK(same_mask(roundtrip(m, &roi), m));
      CHECK(roi == PixelRoi{p.x, p.y, 1, 1});
    }
  }
  SECTION("random densities and odd sizes") {
    for (int i = 0; i < 50; ++i) {
      const int w = 1 + static_cast<int>(rng() % 300), h = 1 + static_cast<int>(rng() % 200);
      const double density = (rng() % 101) / 100.0;
      cv::Mat m(h, w, CV_8UC1);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          m.at<uint8_t>(y, x) =
              (rng() % 1000) < density * 1000 ? static_cast<uint8_t>(1 + rng() % 255) : 0;
      CHECK(same_mask(roundtrip(m), m));
    }
  }
  SECTION("noisy human shape and a non-contiguous view") {
    cv::Mat m = human_shape(800, 600);
    for (int i = 0; i < 2000; ++i) {
      // Column first: the order x86-64 GCC evaluated the arguments in (unspecified in C++).
      const int col = static_cast<int>(rng() % 800), row = static_cast<int>(rng() % 600);
      m.at<uint8_t>(row, col) ^= 255;
    }
    CHECK(same_mask(roundtrip(m), m));
    cv::Mat big = human_shape(1000, 700);
    cv::Mat view = big(cv::Rect(100, 50, 800, 600));  // rows not contiguous in memory
    CHECK(same_mask(roundtrip(view), view));
  }
  SECTION("foreground touching the ROI's right edge wraps into the next row") {
    cv::Mat m(10, 10, CV_8UC1, cv::Scalar(0));
    m(cv::Rect(5, 2, 5, 3)).setTo(255);
    m(cv::Rect(2, 3, 3, 1)).setTo(255);
    CHECK(same_mask(roundtrip(m), m));
  }
}

TEST_CASE("a clean human silhouette at 800x600 encodes to a few hundred bytes") {
  size_t bytes = 0;
  roundtrip(human_shape(800, 600), nullptr, &bytes);
  CHECK(bytes < 3000);
}

TEST_CASE("decoder rejects hostile payloads with the right error") {
  cv::Mat m = human_shape(200, 150), out;
  std::vector<uint8_t> good;
  SilhouetteEncoder().encode(m, good);
  auto decode = [&](std::vector<uint8_t> p, DecodeLimits lim = {}) {
    return decode_silhouette(p, lim, out);
  };
  REQUIRE(decode(good) == CodecError::kNone);

  CHECK(decode({}) == CodecError::kTruncatedHeader);
  CHECK(decode({good.begin(), good.begin() + 19}) == CodecError::kTruncatedHeader);
  auto p = good;
  p[0] = 'X';
  CHECK(decode(p) == CodecError::kBadMagic);
  p = good;
  p[2] = 9;
  CHECK(decode(p) == CodecError::kUnsupportedVersion);
  p = good;
  p[3] = 1;
  CHECK(decode(p) == CodecError::kBadFlags);
  CHECK(decode(good, {100, 100}) == CodecError::kImageTooLarge);
  p = good;
  p[4] = p[5] = 0;
  CHECK(decode(p) == CodecError::kEmptyImage);
  p = good;
  p[8] = 0xff;
  p[9] = 0x00;  // roi_x = 255 > width - roi_w
  CHECK(decode(p) == CodecError::kRoiOutsideImage);
  p = good;
  p[16] = p[17] = p[18] = p[19] = 0xff;
  CHECK(decode(p) == CodecError::kTooManyRuns);
  p = {good.begin(), good.end() - 3};
  CHECK(decode(p) != CodecError::kNone);
  p = good;
  p.push_back(0);
  CHECK(decode(p) == CodecError::kTrailingBytes);
  p = good;
  p.insert(p.begin() + 20, {0xff, 0xff, 0xff, 0xff, 0xff, 0x7f});  // 42-bit varint
  CHECK(decode(p) != CodecError::kNone);
  p = good;
  p[20] = 0xfe;
  p[21] = 0xff;
  p[22] = 0x7f;  // first run longer than the ROI
  CHECK(decode(p) != CodecError::kNone);

  // Oversized declaration: 8192x8192 image claimed by a 20-byte payload, decoder capped at 1024.
  std::vector<uint8_t> huge = {'H', 'S', 1, 0, 0x00, 0x20, 0x00, 0x20, 0, 0,
                               0,   0,   0, 0, 0,    0,    0,    0,    0, 0};
  CHECK(decode(huge, {1024, 1024}) == CodecError::kImageTooLarge);
  for (auto e = static_cast<int>(CodecError::kNone);
       e <= static_cast<int>(CodecError::kTrailingBytes); ++e)
    CHECK(std::string(to_string(static_cast<CodecError>(e))).size() > 1);
}

TEST_CASE("decoder survives random payloads") {
  std::mt19937 rng(99);
  cv::Mat out;
  int accepted = 0;
  for (int i = 0; i < 50000; ++i) {
    std::vector<uint8_t> p(rng() % 48);
    for (auto& b : p) b = static_cast<uint8_t>(rng());
    if (p.size() >= 4 && rng() % 2) {
      p[0] = 'H';
      p[1] = 'S';
      p[2] = 1;
      p[3] = 0;
    }
    if (decode_silhouette(p, {512, 512}, out) == CodecError::kNone) ++accepted;
  }
  CHECK(accepted < 50000);
}

TEST_CASE("encoder rejects masks it cannot represent") {
  std::vector<uint8_t> out;
  SilhouetteEncoder enc;
  CHECK_THROWS_WITH(enc.encode(cv::Mat(10, 10, CV_8UC3), out), Catch::Contains("CV_8UC1"));
}
