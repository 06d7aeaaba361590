#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/camera_node/background_subtractor.hpp"
#include "hullpose/camera_node/codebook.hpp"
#include "hullpose/camera_node/horprasert.hpp"
#include "hullpose/camera_node/mask_cleanup.hpp"
#include "hullpose/common/check.hpp"
#include "mask_score.hpp"
#include "synth_sequence.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;

namespace {

// Small sizes and few frames: this also runs under AddressSanitizer in a Debug build.
test::SynthSequence small_sequence(uint64_t seed, int frames = 5) {
  test::SynthSequenceOptions o;
  o.size = {320, 240};
  o.seed = seed;
  o.background_frames = 12;
  o.frames = frames;
  o.drift = 0.12;
  o.shadow_strength = 0.6;
  return test::render_synth_sequence(o);
}

void learn(BackgroundSubtractor& s, const test::SynthSequence& seq) {
  s.begin_learning(seq.background[0].size());
  for (const cv::Mat& b : seq.background) s.learn(b);
  s.end_learning();
}

// Precision/recall over the test frames, after the node's clean-up.
test::Score score(const std::string& method, const test::SynthSequence& seq) {
  auto s = make_subtractor(method, Params("bgs.params"));
  learn(*s, seq);
  MaskCleanup cleanup({});
  test::Score total;
  cv::Mat mask(seq.frames[0].size(), CV_8UC1);
  for (size_t f = 0; f < seq.frames.size(); ++f) {
    s->apply(seq.frames[f], mask);
    cleanup.apply(mask);
    total.add(mask, seq.truth[f]);
  }
  return total;
}

}  // namespace

TEST_CASE(
    "every method separates the person from a shadowed, drifting scene, at least as well as MOG2") {
  for (uint64_t seed : {1u, 2u}) {
    const test::SynthSequence seq = small_sequence(seed);
    const double mog2 = score("mog2", seq).f1();
    for (const std::string method : {"horprasert", "codebook", "sobs"}) {
      const test::Score s = score(method, seq);
      INFO("seed " << seed << " " << method << ": precision " << s.precision() << " recall "
                   << s.recall() << " F1 " << s.f1() << ", MOG2 F1 " << mog2);
      CHECK(s.f1() > 0.9);
      CHECK(s.f1() >= mog2);
    }
    INFO("seed " << seed << " knn");
    CHECK(score("knn", seq).f1() > 0.6);
  }
}

TEST_CASE("an empty scene gives an (almost) empty mask") {
  const test::SynthSequence seq = small_sequence(3, 0);
  cv::Mat mask(seq.background[0].size(), CV_8UC1);
  for (const std::string& method : subtractor_names()) {
    if (method == "threshold") continue;  // not a background model: takes segmented frames
    auto s = make_subtractor(method, Params("bgs.params"));
    learn(*s, seq);
    s->apply(seq.background[0], mask);
    INFO(method);
    CHECK(cv::countNonZero(mask) < static_cast<int>(mask.total() / 200));
  }
}

TEST_CASE("Horprasert labels the cast shadow as shadow, not foreground") {
  test::SynthSequenceOptions o;
  o.size = {320, 240};
  o.background_frames = 12;
  o.frames = 4;
  o.drift = 0;
  o.shadow_strength = 0.6;
  const test::SynthSequence seq = test::render_synth_sequence(o);
  Horprasert h;
  learn(h, seq);
  cv::Mat mask(o.size, CV_8UC1), gray_bg, gray;
  cv::cvtColor(seq.background[0], gray_bg, cv::COLOR_BGR2GRAY);
  int shadowed_total = 0, as_shadow = 0, as_fg = 0;
  for (size_t f = 0; f < seq.frames.size(); ++f) {
    h.apply(seq.frames[f], mask);
    cv::cvtColor(seq.frames[f], gray, cv::COLOR_BGR2GRAY);
    // Pixels the person's shadow darkened clearly, away from the person.
    cv::Mat near_person;
    cv::dilate(seq.truth[f], near_person, cv::Mat(), {-1, -1}, 3);
    const cv::Mat shadowed = (gray < gray_bg * 0.8) & (near_person == 0);
    shadowed_total += cv::countNonZero(shadowed);
    as_shadow += cv::countNonZero(shadowed & (h.classes() == Horprasert::kShadow));
    as_fg += cv::countNonZero(shadowed & (mask != 0));
  }
  REQUIRE(shadowed_total > 50);
  CHECK(as_shadow > shadowed_total * 8 / 10);
  CHECK(as_fg < shadowed_total / 20);
}

TEST_CASE("Codebook keeps few codewords on a static scene") {
  const test::SynthSequence seq = small_sequence(5, 0);
  Codebook cb;
  learn(cb, seq);
  CHECK(cb.mean_codewords() >= 1.0);
  CHECK(cb.mean_codewords() < 1.5);
}

TEST_CASE("methods are chosen by name and their parameters are checked") {
  CHECK(subtractor_names() ==
        std::vector<std::string>{"horprasert", "codebook", "sobs", "mog2", "knn", "threshold"});
  CHECK_THROWS_WITH(make_subtractor("vibe", Params("bgs.params")),
                    Catch::Contains("bgs.method: unknown method 'vibe' (known: horprasert, "
                                    "codebook, sobs, mog2, knn, threshold)"));
  Params bad("cam.yaml: bgs.params");
  bad.set("detection_rate", "2");
  CHECK_THROWS_WITH(make_subtractor("horprasert", bad),
                    Catch::Contains("cam.yaml: bgs.params.detection_rate"));
  Params typo("cam.yaml: bgs.params");
  typo.set("epsilon", "3");
  CHECK_THROWS_WITH(make_subtractor("codebook", typo),
                    Catch::Contains("unknown parameter(s): epsilon"));
  auto s = make_subtractor("sobs", Params("bgs.params"));
  s->begin_learning({8, 8});
  CHECK_THROWS_WITH(s->end_learning(), Catch::Contains("sobs: no background frame"));
}

TEST_CASE("clean-up removes speckle and small blobs, keeps the person and fills pinholes") {
  cv::Mat mask(120, 160, CV_8UC1, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(40, 20, 30, 80), cv::Scalar(255), -1);  // person
  mask.at<uint8_t>(50, 55) = 0;                                        // pinhole
  mask(cv::Rect(45, 70, 3, 3)).setTo(0);                               // a larger pinhole (9 px)
  mask.at<uint8_t>(5, 5) = 255;                                        // speckle
  cv::rectangle(mask, cv::Rect(120, 100, 5, 5), cv::Scalar(255), -1);  // small blob (25 px)
  MaskCleanup cleanup({1, 0, 50, 16});
  cleanup.apply(mask);
  CHECK(mask.at<uint8_t>(50, 55) == 255);
  CHECK(cv::countNonZero(mask(cv::Rect(45, 70, 3, 3))) == 9);
  CHECK(mask.at<uint8_t>(5, 5) == 0);
  CHECK(cv::countNonZero(mask(cv::Rect(115, 95, 15, 15))) == 0);
  CHECK(cv::countNonZero(mask(cv::Rect(40, 20, 30, 80))) > 30 * 80 - 10);
}

TEST_CASE(
    "clean-up fills enclosed holes only: the gaps between limbs stay open, unlike with closing") {
  // Legs 3 px apart below a torso (the gap opens to the background below), an arm resting on
  // the hip around a 10x10 gap of real background (enclosed, larger than max_hole_area), and a
  // 2x2 pinhole in the torso (enclosed, small).
  cv::Mat person(120, 160, CV_8UC1, cv::Scalar(0));
  cv::rectangle(person, cv::Rect(60, 10, 23, 50), cv::Scalar(255), -1);  // torso
  cv::rectangle(person, cv::Rect(60, 60, 10, 50), cv::Scalar(255), -1);  // left leg
  cv::rectangle(person, cv::Rect(73, 60, 10, 50), cv::Scalar(255), -1);  // right leg, 3 px gap
  cv::rectangle(person, cv::Rect(83, 15, 16, 6), cv::Scalar(255), -1);   // upper arm
  cv::rectangle(person, cv::Rect(93, 21, 6, 16), cv::Scalar(255), -1);   // forearm down to the hip
  cv::rectangle(person, cv::Rect(83, 37, 16, 4), cv::Scalar(255), -1);   // hand on the hip
  person(cv::Rect(70, 30, 2, 2)).setTo(0);                               // pinhole
  const cv::Rect legs_gap(70, 62, 3, 45), arm_gap(83, 21, 10, 16);
  REQUIRE(cv::countNonZero(person(arm_gap)) == 0);

  cv::Mat filled = person.clone();
  MaskCleanup({0, 0, 0, 64}).apply(filled);
  CHECK(cv::countNonZero(filled(legs_gap)) == 0);
  CHECK(cv::countNonZero(filled(arm_gap)) == 0);  // 160 px: more than max_hole_area
  CHECK(cv::countNonZero(filled(cv::Rect(70, 30, 2, 2))) == 4);
  CHECK(cv::countNonZero(filled) == cv::countNonZero(person) + 4);

  cv::Mat closed = person.clone();
  MaskCleanup({0, 2, 0, 0}).apply(closed);
  CHECK(cv::countNonZero(closed(legs_gap)) > 0);  // what the default avoids: the legs joined
}

TEST_CASE("the threshold method passes pre-segmented frames through unchanged") {
  cv::Mat truth = cv::Mat::zeros(48, 64, CV_8UC1);
  cv::rectangle(truth, cv::Rect(10, 5, 20, 30), cv::Scalar(255), cv::FILLED);
  cv::Mat bgr, mask(truth.size(), CV_8UC1);
  cv::cvtColor(truth, bgr, cv::COLOR_GRAY2BGR);
  auto s = make_subtractor("threshold", Params("bgs.params"));
  s->begin_learning(truth.size());
  s->end_learning();
  s->apply(bgr, mask);
  CHECK(cv::countNonZero(mask != truth) == 0);
  Params bad("bgs.params");
  bad.set("level", "0");
  CHECK_THROWS_WITH(make_subtractor("threshold", bad),
                    Catch::Contains("bgs.params.level: must be in [1, 255]"));
}
