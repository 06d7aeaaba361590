// The synthetic frame source (the simulated rig rendered live): built only where the build has it
// (HULLPOSE_SYNTHETIC_SOURCE, off in a board's production build).
#include <catch2/catch.hpp>
#include <opencv2/core.hpp>

#include "hullpose/camera_node/frame_source.hpp"
#include "hullpose/camera_node/synthetic_source.hpp"
#include "hullpose/synth/rig_gen.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;

TEST_CASE("the synthetic source renders this camera's view of the synthetic rig") {
  synth::RingRigSpec spec;
  spec.width = 160;
  spec.height = 120;
  const Rig rig = synth::make_ring_rig(spec);
  SourceContext c;
  c.camera_id = 3;
  c.camera = *rig.find(3);
  c.volume = rig.volume;
  Params p("source");
  p.set("motion", "walk");
  p.set("empty_frames", "2");
  p.set("frames", "3");
  p.set("fps", "25");
  p.set("start_utime", "5000000");
  auto src = SourceRegistry::builtin().create("synthetic", p, c);
  auto* synthetic = dynamic_cast<SyntheticSource*>(src.get());
  REQUIRE(synthetic);
  src->start();
  Frame f;
  for (int i = 0; i < 5; ++i) {
    REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);
    CHECK(f.sequence == i);
    CHECK(f.capture_utime == 5000000 + i * 40000);
    CHECK(f.image.size() == cv::Size(160, 120));
    CHECK(f.image.type() == CV_8UC3);
    if (i < 2)
      CHECK(cv::countNonZero(synthetic->truth()) == 0);  // the empty room, to learn from
    else
      CHECK(cv::countNonZero(synthetic->truth()) > 50);
  }
  CHECK(src->grab(f, 0) == GrabStatus::kEndOfStream);

  // Triggered: after the empty room, trigger k shows motion frame k, whatever came before.
  auto triggered = SourceRegistry::builtin().create("synthetic", p, c);
  triggered->start();
  for (int i = 0; i < 2; ++i) REQUIRE(triggered->grab(f, 0) == GrabStatus::kFrame);
  triggered->expose(1, 123);
  REQUIRE(triggered->grab(f, 0) == GrabStatus::kFrame);
  CHECK(f.capture_utime == 123);
  src->start();
  for (int i = 0; i < 4; ++i)
    REQUIRE(src->grab(f, 0) == GrabStatus::kFrame);  // 2 empty + motion 0, 1
  CHECK(cv::countNonZero(dynamic_cast<SyntheticSource&>(*triggered).truth() !=
                         synthetic->truth()) == 0);

  Params bad("cam.yaml: source");
  bad.set("motion", "moonwalk");
  auto unknown = SourceRegistry::builtin().create("synthetic", bad, c);
  CHECK_THROWS_WITH(unknown->start(), Catch::Contains("moonwalk"));
}
