// scratch
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include "synthetic_scene.hpp"
#include "hullpose/camera_node/background_subtractor.hpp"
#include "hullpose/camera_node/mask_cleanup.hpp"
#include "hullpose/common/time.hpp"
using namespace hullpose;
int main(int argc, char** argv) {
  cv::setNumThreads(1);
  test::SceneOptions o; o.size = {640, 480}; o.frames = 20;
  if (argc > 2) o.shadow_strength = atof(argv[2]);
  test::SyntheticScene scene(o);
  cv::Mat bgr, gt, mask(o.size, CV_8UC1);
  for (const auto& m : camera_node::subtractor_names()) {
    if (argc > 1 && m != argv[1] && std::string(argv[1]) != "all") continue;
    camera_node::Params p("x");
    auto s = camera_node::make_subtractor(m, p);
    s->begin_learning(o.size);
    for (int k = 0; k < 30; ++k) { scene.background_frame(k, bgr); s->learn(bgr); }
    s->end_learning();
    camera_node::MaskCleanup clean({1, 2, 64});
    test::Score raw, post; int64_t us = 0;
    for (int f = 0; f < o.frames; ++f) {
      scene.frame(f, bgr, gt);
      StageTimer t; s->apply(bgr, mask); us += t.elapsed_us();
      raw.add(mask, gt);
      if (f == o.frames / 2) { cv::imwrite("/tmp/cn_" + m + "_raw.png", mask); cv::imwrite("/tmp/cn_frame.png", bgr); }
      clean.apply(mask); post.add(mask, gt);
    }
    std::printf("%-10s raw P %.3f R %.3f F1 %.3f | post P %.3f R %.3f F1 %.3f | %.2f ms\n", m.c_str(), raw.precision(), raw.recall(), raw.f1(), post.precision(), post.recall(), post.f1(), us / 1e3 / o.frames);
  }
}
