#include "synthetic_scene.hpp"

#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace hullpose::test {
namespace {

cv::Scalar random_colour(cv::RNG& rng, double lo, double hi) {
  return cv::Scalar(rng.uniform(lo, hi), rng.uniform(lo, hi), rng.uniform(lo, hi));
}

// Smooth random texture with standard deviation `sd` per channel, CV_32FC3.
cv::Mat texture(cv::Size size, cv::RNG& rng, double sd, double blur) {
  cv::Mat t(size, CV_32FC3);
  rng.fill(t, cv::RNG::UNIFORM, cv::Scalar::all(-1), cv::Scalar::all(1));
  cv::GaussianBlur(t, t, cv::Size(), blur);
  cv::Scalar mean, dev;
  cv::meanStdDev(t.reshape(1), mean, dev);
  return t * (sd / std::max(1e-9, dev[0]));
}

}  // namespace

SyntheticScene::SyntheticScene(SceneOptions options) : options_(options) {
  cv::RNG rng(options_.seed);
  const cv::Size s = options_.size;
  const int horizon = s.height * 3 / 5;
  background_.create(s, CV_32FC3);
  background_.setTo(random_colour(rng, 90, 170));  // wall
  cv::rectangle(background_, cv::Rect(0, horizon, s.width, s.height - horizon), random_colour(rng, 60, 130), -1);
  // Furniture and posters: flat patches of other colours.
  for (int i = 0; i < 10; ++i) {
    const int w = rng.uniform(s.width / 20, s.width / 5), h = rng.uniform(s.height / 20, s.height / 4);
    const cv::Rect r(rng.uniform(0, s.width - w), rng.uniform(0, s.height - h), w, h);
    cv::rectangle(background_, r, random_colour(rng, 30, 230), -1);
  }
  // Fine texture (wood, carpet) and broad shading.
  background_ += texture(s, rng, 14.0, 1.2);
  background_ += texture(s, rng, 12.0, s.width / 40.0);
  clothes_.create(s, CV_32FC3);
  clothes_ = texture(s, rng, 18.0, 1.5);
}

void SyntheticScene::person(int f, cv::Mat& mask, cv::Mat& shadow) const {
  const cv::Size s = options_.size;
  const double t = options_.frames > 1 ? static_cast<double>(f) / (options_.frames - 1) : 0.0;
  const double u = s.height / 480.0;  // scale with resolution
  const int cx = static_cast<int>(s.width * (0.2 + 0.6 * t));
  const int feet = s.height * 9 / 10;
  const double swing = 0.5 * std::sin(2 * std::numbers::pi * 2.5 * t);
  mask.create(s, CV_8UC1);
  mask.setTo(0);
  const cv::Scalar fg(255);
  const int hip_y = feet - static_cast<int>(150 * u), sho_y = hip_y - static_cast<int>(130 * u);
  const auto pt = [](double x, double y) { return cv::Point(static_cast<int>(x), static_cast<int>(y)); };
  cv::circle(mask, pt(cx, sho_y - 35 * u), static_cast<int>(22 * u), fg, -1);                      // head
  cv::ellipse(mask, pt(cx, (hip_y + sho_y) / 2.0), cv::Size(static_cast<int>(32 * u), static_cast<int>(72 * u)), 0, 0,
              360, fg, -1);                                                                          // torso
  const int limb = std::max(3, static_cast<int>(16 * u));
  const double leg = 150 * u, arm = 120 * u;
  cv::line(mask, pt(cx - 12 * u, hip_y), pt(cx - 12 * u + leg * std::sin(swing), hip_y + leg * std::cos(swing)), fg, limb);
  cv::line(mask, pt(cx + 12 * u, hip_y), pt(cx + 12 * u - leg * std::sin(swing), hip_y + leg * std::cos(swing)), fg, limb);
  cv::line(mask, pt(cx - 30 * u, sho_y + 8 * u), pt(cx - 30 * u - arm * std::sin(swing), sho_y + arm * std::cos(swing)), fg,
           limb * 3 / 4);
  cv::line(mask, pt(cx + 30 * u, sho_y + 8 * u), pt(cx + 30 * u + arm * std::sin(swing), sho_y + arm * std::cos(swing)), fg,
           limb * 3 / 4);
  // Cast shadow: the silhouette sheared onto the floor and the wall, softened.
  cv::Mat sh(s, CV_8UC1, cv::Scalar(0));
  const cv::Point2f src[3] = {cv::Point2f(static_cast<float>(cx), static_cast<float>(feet)),
                              cv::Point2f(static_cast<float>(cx), static_cast<float>(feet - 100)),
                              cv::Point2f(static_cast<float>(cx + 100), static_cast<float>(feet))};
  const cv::Point2f dst[3] = {cv::Point2f(static_cast<float>(cx), static_cast<float>(feet)),
                              cv::Point2f(static_cast<float>(cx + 90), static_cast<float>(feet - 55)),
                              cv::Point2f(static_cast<float>(cx + 100), static_cast<float>(feet))};
  cv::warpAffine(mask, sh, cv::getAffineTransform(src, dst), s, cv::INTER_NEAREST);
  sh.convertTo(shadow, CV_32F, 1.0 / 255);
  cv::GaussianBlur(shadow, shadow, cv::Size(), 4.0 * u);
}

void SyntheticScene::finish(cv::Mat& scene, double gain_phase, uint64_t noise_seed, cv::Mat& bgr) const {
  const double g = options_.drift * gain_phase;
  // Slightly warmer as it brightens: blue, green, red gains differ.
  cv::multiply(scene, cv::Scalar(1 + 0.7 * g, 1 + 0.85 * g, 1 + g), scene);
  cv::Mat noise(scene.size(), CV_32FC3);
  cv::RNG rng(noise_seed);
  rng.fill(noise, cv::RNG::NORMAL, cv::Scalar::all(0), cv::Scalar::all(options_.noise_sigma));
  scene += noise;
  scene.convertTo(bgr, CV_8UC3);  // saturates at 0 and 255 like a sensor
}

void SyntheticScene::background_frame(int k, cv::Mat& bgr) const {
  cv::Mat scene = background_.clone();
  finish(scene, 0.0, options_.seed * 7919 + 1000003 + static_cast<uint64_t>(k), bgr);
}

void SyntheticScene::frame(int f, cv::Mat& bgr, cv::Mat& mask) const {
  cv::Mat shadow;
  person(f, mask, shadow);
  cv::Mat scene = background_.clone();
  cv::Mat light;
  cv::merge(std::vector<cv::Mat>(3, 1.0 - options_.shadow_strength * shadow), light);
  cv::multiply(scene, light, scene);
  // The person: clothes colour by height (shirt, trousers) plus texture.
  cv::RNG rng(options_.seed * 31 + 17);
  const cv::Scalar shirt = random_colour(rng, 40, 220), trousers = random_colour(rng, 20, 120);
  cv::Mat person(scene.size(), CV_32FC3);
  const int split = options_.size.height * 9 / 10 - static_cast<int>(150 * options_.size.height / 480.0);
  person.rowRange(0, split).setTo(shirt);
  person.rowRange(split, person.rows).setTo(trousers);
  person += clothes_;
  person.copyTo(scene, mask);
  const double phase = options_.frames > 1 ? std::sin(std::numbers::pi * f / (options_.frames - 1)) : 0.0;
  finish(scene, phase, options_.seed * 104729 + static_cast<uint64_t>(f), bgr);
}

void Score::add(const cv::Mat& mask, const cv::Mat& truth) {
  for (int y = 0; y < mask.rows; ++y) {
    const uint8_t* m = mask.ptr<uint8_t>(y);
    const uint8_t* t = truth.ptr<uint8_t>(y);
    for (int x = 0; x < mask.cols; ++x) {
      const bool a = m[x] != 0, b = t[x] != 0;
      tp += a && b;
      fp += a && !b;
      fn += !a && b;
    }
  }
}

}  // namespace hullpose::test
