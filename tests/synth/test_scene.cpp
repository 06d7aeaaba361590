#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/synth/rig_gen.hpp"
#include "hullpose/synth/scene.hpp"

using namespace hullpose;
using namespace hullpose::synth;

TEST_CASE("the live camera renderer: colour frame, exact mask, background, shadows") {
  const Rig rig = make_ring_rig({});
  const auto motion = make_builtin_motion("wave", {});
  BodyShape body;
  const Scene scene(SceneOptions{}, 5);
  CameraRenderer cam(*motion, body, rig.cameras[1], scene, 30);
  cv::Mat bgr, mask, background;
  cam.render(10, bgr, mask);
  cam.render_background(0, background);
  REQUIRE(bgr.type() == CV_8UC3);
  REQUIRE(mask.type() == CV_8UC1);

  // The mask is exactly the silhouette renderer's.
  JointPositions q;
  motion->sample(10 / 30.0, q);
  std::vector<Primitive> prims;
  pose_avatar(body, q, prims);
  ViewRenderer view(rig.cameras[1]);
  cv::Mat expected;
  view.render_mask(prims, expected);
  CHECK(cv::countNonZero(mask != expected) == 0);

  // Background subtraction is possible: the person differs from the empty room, most of the
  // rest of the image does not (sensor noise, drift and the shadow aside).
  cv::Mat diff;
  cv::absdiff(bgr, background, diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
  const double person = cv::mean(diff, mask)[0];
  cv::Mat outside = mask == 0;
  const double rest = cv::mean(diff, outside)[0];
  CHECK(person > 25);
  CHECK(rest < 15);
  // The shadow darkens some floor near the person, and only there.
  cv::Mat darker = (diff > 12) & outside;
  CHECK(cv::countNonZero(darker) > 200);
  CHECK(cv::countNonZero(darker) < 0.1 * outside.total());

  // Frames are reproducible and buffers reused.
  const uint8_t* data = bgr.data;
  cv::Mat again;
  cam.render(10, again, mask);
  CHECK(cv::norm(bgr, again, cv::NORM_INF) == 0);
  cam.render(11, bgr, mask);
  CHECK(bgr.data == data);
}

TEST_CASE("illumination drifts slowly and flicker is per frame") {
  SceneOptions o;
  o.flicker = 0.05;
  const Scene scene(o, 1);
  CHECK(std::abs(scene.gain(0, 0, 0.0) - scene.gain(0, 0, 0.0)) == 0);
  SceneOptions steady;
  steady.flicker = 0;
  const Scene calm(steady, 1);
  CHECK(std::abs(calm.gain(0, 0, 0) - calm.gain(0, 1, 1 / 30.0)) < 0.001);  // slow drift
  CHECK(std::abs(calm.gain(0, 0, 0) - calm.gain(0, 300, 10)) > 0.001);
  double spread = 0;
  for (int f = 0; f < 100; ++f) spread += std::abs(scene.gain(0, f, 0) - calm.gain(0, f, 0));
  CHECK(spread / 100 > 0.01);
}
