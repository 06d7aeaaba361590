#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/camera_node/background_subtractor.hpp"
#include "hullpose/camera_node/codebook.hpp"
#include "hullpose/camera_node/horprasert.hpp"
#include "hullpose/camera_node/mask_cleanup.hpp"
#include "hullpose/common/check.hpp"
#include "synthetic_scene.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;

namespace {

test::SceneOptions small_scene(uint64_t seed) {
  test::SceneOptions o;
  o.size = {320, 240};
  o.seed = seed;
  o.frames = 8;
  return o;
}

void learn(BackgroundSubtractor& s, const test::SyntheticScene& scene, int frames) {
  cv::Mat bgr;
  s.begin_learning(scene.options().size);
  for (int k = 0; k < frames; ++k) {
    scene.background_frame(k, bgr);
    s.learn(bgr);
  }
  s.end_learning();
}

// Precision/recall over the test frames, after the node's clean-up.
test::Score score(const std::string& method, const test::SyntheticScene& scene) {
  auto s = make_subtractor(method, Params("bgs.params"));
  learn(*s, scene, 20);
  MaskCleanup cleanup({1, 2, 32});
  test::Score total;
  cv::Mat bgr, truth, mask(scene.options().size, CV_8UC1);
  for (int f = 0; f < scene.options().frames; ++f) {
    scene.frame(f, bgr, truth);
    s->apply(bgr, mask);
    cleanup.apply(mask);
    total.add(mask, truth);
  }
  return total;
}

}  // namespace

TEST_CASE("every method separates the person from a shadowed, drifting scene, at least as well as MOG2") {
  for (uint64_t seed : {1u, 2u}) {
    const test::SyntheticScene scene(small_scene(seed));
    const double mog2 = score("mog2", scene).f1();
    for (const std::string method : {"horprasert", "codebook", "sobs"}) {
      const test::Score s = score(method, scene);
      INFO("seed " << seed << " " << method << ": precision " << s.precision() << " recall " << s.recall()
                   << " F1 " << s.f1() << ", MOG2 F1 " << mog2);
      CHECK(s.f1() > 0.9);
      CHECK(s.f1() >= mog2);
    }
    INFO("seed " << seed << " knn");
    CHECK(score("knn", scene).f1() > 0.6);
  }
}

TEST_CASE("an empty scene gives an (almost) empty mask") {
  const test::SyntheticScene scene(small_scene(3));
  cv::Mat bgr, mask(scene.options().size, CV_8UC1);
  for (const std::string& method : subtractor_names()) {
    auto s = make_subtractor(method, Params("bgs.params"));
    learn(*s, scene, 20);
    scene.background_frame(100, bgr);  // noise not seen while learning
    s->apply(bgr, mask);
    INFO(method);
    CHECK(cv::countNonZero(mask) < static_cast<int>(mask.total() / 200));
  }
}

TEST_CASE("Horprasert labels the cast shadow as shadow, not foreground") {
  test::SceneOptions o = small_scene(4);
  o.drift = 0;
  const test::SyntheticScene scene(o);
  Horprasert h;
  learn(h, scene, 20);
  cv::Mat bgr, truth, mask(o.size, CV_8UC1);
  scene.frame(4, bgr, truth);
  h.apply(bgr, mask);
  // Pixels that the shadow darkened by a lot but that are not the person.
  cv::Mat empty;
  scene.background_frame(0, empty);
  cv::Mat bright_drop;
  cv::Mat gray_bg, gray_fr;
  cv::cvtColor(empty, gray_bg, cv::COLOR_BGR2GRAY);
  cv::cvtColor(bgr, gray_fr, cv::COLOR_BGR2GRAY);
  cv::Mat shadowed = (gray_fr < gray_bg * 0.7) & (truth == 0);
  const int n = cv::countNonZero(shadowed);
  REQUIRE(n > 100);
  const int as_shadow = cv::countNonZero(shadowed & (h.classes() == Horprasert::kShadow));
  const int as_fg = cv::countNonZero(shadowed & (mask != 0));
  CHECK(as_shadow > n * 8 / 10);
  CHECK(as_fg < n / 20);
}

TEST_CASE("Codebook keeps few codewords on a static scene") {
  const test::SyntheticScene scene(small_scene(5));
  Codebook cb;
  learn(cb, scene, 20);
  CHECK(cb.mean_codewords() >= 1.0);
  CHECK(cb.mean_codewords() < 1.5);
}

TEST_CASE("methods are chosen by name and their parameters are checked") {
  CHECK(subtractor_names() == std::vector<std::string>{"horprasert", "codebook", "sobs", "mog2", "knn"});
  CHECK_THROWS_WITH(make_subtractor("vibe", Params("bgs.params")),
                    Catch::Contains("bgs.method: unknown method 'vibe' (known: horprasert, codebook, sobs, mog2, knn)"));
  Params bad("cam.yaml: bgs.params");
  bad.set("detection_rate", "2");
  CHECK_THROWS_WITH(make_subtractor("horprasert", bad), Catch::Contains("cam.yaml: bgs.params.detection_rate"));
  Params typo("cam.yaml: bgs.params");
  typo.set("epsilon", "3");
  CHECK_THROWS_WITH(make_subtractor("codebook", typo), Catch::Contains("unknown parameter(s): epsilon"));
  auto s = make_subtractor("sobs", Params("bgs.params"));
  s->begin_learning({8, 8});
  CHECK_THROWS_WITH(s->end_learning(), Catch::Contains("sobs: no background frame"));
}

TEST_CASE("clean-up removes speckle and small blobs, keeps the person and fills pinholes") {
  cv::Mat mask(120, 160, CV_8UC1, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(40, 20, 30, 80), cv::Scalar(255), -1);  // person
  mask.at<uint8_t>(50, 55) = 0;                                        // pinhole
  mask.at<uint8_t>(5, 5) = 255;                                        // speckle
  cv::rectangle(mask, cv::Rect(120, 100, 5, 5), cv::Scalar(255), -1);  // small blob (25 px)
  MaskCleanup cleanup({1, 2, 50});
  cleanup.apply(mask);
  CHECK(mask.at<uint8_t>(50, 55) == 255);
  CHECK(mask.at<uint8_t>(5, 5) == 0);
  CHECK(cv::countNonZero(mask(cv::Rect(115, 95, 15, 15))) == 0);
  CHECK(cv::countNonZero(mask(cv::Rect(40, 20, 30, 80))) > 30 * 80 - 10);
}
