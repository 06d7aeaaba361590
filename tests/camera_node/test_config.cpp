#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/camera_node/params.hpp"
#include "hullpose/common/check.hpp"
#include "scratch_dir.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;
namespace fs = std::filesystem;

namespace {

fs::path write(const std::string& name, const std::string& text) {
  static const test::ScratchDir dir("hullpose_test_camera_config");  // this process's
  const fs::path p = dir.path / name;
  std::ofstream(p) << text;
  return p;
}

const char* kGood = R"(%YAML:1.0
camera_id: 3
rig_file: rig.yaml
source:
  type: file
  path: cam3/rgb_%06d.png
  fps: 25
bgs:
  method: sobs
  learn_frames: 12
  params:
    epsilon_online: 0.01
post:
  open_radius: 0
  min_blob_area: 10
  roi: [10, 20, 300, 200]
lcm:
  url: "udpm://239.255.76.67:7690?ttl=0"
  queue_depth: 2
)";

std::string error_of(const std::string& yaml) {
  try {
    load_node_config(write("bad.yaml", yaml));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const size_t pos = s.find(from);
  REQUIRE(pos != std::string::npos);
  return s.replace(pos, from.size(), to);
}

}  // namespace

TEST_CASE("a complete node config is read with every field") {
  const fs::path p = write("good.yaml", kGood);
  const NodeConfig c = load_node_config(p);
  CHECK(c.camera_id == 3);
  CHECK(c.rig_file == p.parent_path() / "rig.yaml");
  CHECK(c.source.type == "file");
  CHECK(c.source.params.get_string("path", "") == "cam3/rgb_%06d.png");
  CHECK(c.source.params.get_double("fps", 0, 0, 100) == 25.0);
  CHECK(c.bgs.method == "sobs");
  CHECK(c.bgs.learn_frames == 12);
  CHECK(c.bgs.params.get_double("epsilon_online", 0, 0, 1) == Approx(0.01));
  CHECK(c.post.open_radius == 0);
  CHECK(c.post.close_radius == 0);  // default kept
  CHECK(c.post.max_hole_area == 64);
  CHECK(c.post.min_blob_area == 10);
  CHECK(c.post.roi == cv::Rect(10, 20, 300, 200));
  CHECK(c.lcm.url == "udpm://239.255.76.67:7690?ttl=0");
  CHECK(c.lcm.queue_depth == 2);
  CHECK(c.lcm.silhouette_channel == "SILHOUETTE");
}

TEST_CASE("config errors name the file and the field") {
  CHECK_THAT(error_of(replace(kGood, "camera_id: 3", "camera_id: 99")),
             Catch::Matches(".*bad.yaml:[0-9]+: camera_id: must be in \\[0, 63\\], got 99.*"));
  CHECK_THAT(error_of(replace(kGood, "camera_id: 3\n", "")), Catch::Contains("camera_id: missing"));
  CHECK_THAT(error_of(replace(kGood, "  method: sobs\n", "")),
             Catch::Contains("bgs.method: missing"));
  CHECK_THAT(error_of(replace(kGood, "learn_frames: 12", "learn_frames: many")),
             Catch::Contains("bgs.learn_frames: must be an integer"));
  CHECK_THAT(error_of(replace(kGood, "roi: [10, 20, 300, 200]", "roi: [10, 20]")),
             Catch::Contains("post.roi"));
  CHECK_THAT(error_of(replace(kGood, "queue_depth: 2", "queue_dept: 2")),
             Catch::Contains("lcm.queue_dept: unknown field"));
  CHECK_THAT(error_of(replace(kGood, "post:", "postt:")), Catch::Contains("postt: unknown field"));
  CHECK_THAT(error_of("%YAML:1.0\ncamera_id: [unclosed\n"), Catch::Contains("bad.yaml"));
  CHECK_THAT(error_of(""), Catch::Contains("bad.yaml"));
  try {
    load_node_config("/nonexistent/camera.yaml");
    FAIL("no error");
  } catch (const Error& e) {
    CHECK_THAT(e.what(), Catch::Contains("/nonexistent/camera.yaml: config file not found"));
  }
}

TEST_CASE("stage parameters are typed, ranged and must all be known") {
  Params p("cam.yaml: bgs.params");
  p.set("rate", "0.5");
  p.set("count", "7");
  p.set("flag", "true");
  p.set("typo", "1");
  CHECK(p.get_double("rate", 0, 0, 1) == 0.5);
  CHECK(p.get_int("count", 0, 0, 10) == 7);
  CHECK(p.get_bool("flag", false));
  CHECK(p.get_int("absent", 42, 0, 100) == 42);
  CHECK_THROWS_WITH(p.expect_all_used(),
                    Catch::Contains("cam.yaml: bgs.params: unknown parameter(s): typo"));
  CHECK_THROWS_WITH(p.get_int("count", 0, 0, 5),
                    Catch::Contains("cam.yaml: bgs.params.count: must be in [0, 5], got 7"));
  CHECK_THROWS_WITH(p.get_int("rate", 0, 0, 5),
                    Catch::Contains("bgs.params.rate: must be an integer"));
  CHECK_THROWS_WITH(p.get_bool("rate", false), Catch::Contains("must be true or false"));
  p.set("nan", "nan");
  CHECK_THROWS_WITH(p.get_double("nan", 0, 0, 1),
                    Catch::Contains("bgs.params.nan: must be a number"));
  CHECK_THROWS_WITH(p.require_string("missing"),
                    Catch::Contains("bgs.params.missing: missing (required)"));
}

TEST_CASE("the trigger section names the input and is checked field by field") {
  const NodeConfig none = load_node_config(write("good.yaml", kGood));
  CHECK_FALSE(none.trigger.enabled);  // free-running

  const fs::path gpio =
      write("gpio.yaml", std::string(kGood) +
                             "trigger:\n  edges: gpiod\n  chip: gpiochip0\n  line: 17\n"
                             "  max_residual_us: 3000\n  wait_ms: 20\n");
  const NodeConfig g = load_node_config(gpio);
  CHECK(g.trigger.enabled);
  CHECK(g.trigger.edges == "gpiod:gpiochip0:17");
  CHECK(g.trigger.channel == "TRIGGER");
  CHECK(g.trigger.max_residual_us == 3000);
  CHECK(g.trigger.wait_ms == 20);
  CHECK(g.trigger.clock_offset_ms == 0);
  CHECK_FALSE(g.trigger.free_running);

  const NodeConfig w = load_node_config(
      write("wire.yaml", std::string(kGood) + "trigger: { edges: wire, path: run/wire.sock, "
                                              "channel: TRIG2, clock_offset_ms: -2000 }\n"));
  CHECK(w.trigger.edges == "wire:" + (w.base_dir / "run/wire.sock").string());
  CHECK(w.trigger.channel == "TRIG2");
  CHECK(w.trigger.clock_offset_ms == -2000);

  const auto with = [](const std::string& trigger) {
    return error_of(std::string(kGood) + "trigger:\n" + trigger);
  };
  CHECK_THAT(with("  chip: gpiochip0\n"),
             Catch::Matches(".*bad.yaml:[0-9]+: trigger.edges: missing \\(required\\).*"));
  CHECK_THAT(with("  edges: serial\n"),
             Catch::Contains("trigger.edges: unknown trigger input 'serial'"));
  CHECK_THAT(with("  edges: gpiod\n  chip: gpiochip0\n"),
             Catch::Contains("trigger.line: missing (required)"));
  CHECK_THAT(with("  edges: gpiod\n  chip: gpiochip0\n  line: -1\n"),
             Catch::Contains("trigger.line: must be in [0, 65535]"));
  CHECK_THAT(with("  edges: gpiod\n  chip: gpiochip0\n  line: 1\n  path: x\n"),
             Catch::Contains("trigger.path: only for edges: wire"));
  CHECK_THAT(with("  edges: wire\n"), Catch::Contains("trigger.path: missing (required)"));
  CHECK(load_node_config(
            write("free.yaml",
                  std::string(kGood) + "trigger: { edges: wire, path: w, camera: free_running }\n"))
            .trigger.free_running);
  CHECK_THAT(with("  edges: wire\n  path: w\n  camera: sometimes\n"),
             Catch::Contains("trigger.camera: 'sometimes' is not triggered or free_running"));
  CHECK_THAT(with("  edges: wire\n  path: w.sock\n  line: 3\n"),
             Catch::Contains("trigger.line: only for edges: gpiod"));
  CHECK_THAT(with("  edges: wire\n  path: w.sock\n  wait_ms: 99999\n"),
             Catch::Contains("trigger.wait_ms: must be in [0, 10000]"));
  CHECK_THAT(with("  edges: wire\n  path: w.sock\n  mode: nearest\n"),
             Catch::Contains("trigger.mode: unknown field"));
}
