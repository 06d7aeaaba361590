// The camera node wired to the trigger (config trigger:): the real trigger master (firmware_sync)
// pulses a simulated wire and announces on LCM (UDP multicast, loopback, a port of its own); the
// node replays a recording whose frame k shows k, as a simulated sensor that exposes exactly one
// frame per edge. Every edge must give exactly one silhouette, carrying the master's sequence and
// utime and showing that sequence's frame, even on a board whose clock is 2 s off.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "hullpose/camera_node/camera_node.hpp"
#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/clock.hpp"
#include "hullpose/common/silhouette_codec.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/firmware_sync/trigger_master.hpp"
#include "hullpose/msg/wire.hpp"
#include "hullpose_msg/silhouette_t.hpp"
#include "test_dataset.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;
namespace fs = std::filesystem;

namespace {

constexpr const char* kUrl = "udpm://239.255.76.67:7684?ttl=0";
constexpr int kRecorded = 64;  // frames in the recording
constexpr int kPulses = 40;

// Frame k of the recording: a bar whose position and width encode k.
cv::Mat frame_mask(int k) {
  cv::Mat m = cv::Mat::zeros(48, 64, CV_8UC1);
  cv::rectangle(m, cv::Rect(k % 50, 4 + k / 50 * 10, 3 + k % 7, 30), cv::Scalar(255), cv::FILLED);
  return m;
}

struct Received {
  std::map<int64_t, hullpose_msg::silhouette_t> by_seq;
  int duplicates = 0;
  void on_silhouette(std::span<const uint8_t> bytes) {
    hullpose_msg::silhouette_t m;
    REQUIRE(wire::decode(bytes, m));
    if (!by_seq.emplace(m.trigger_seq, m).second) ++duplicates;
  }
};

}  // namespace

TEST_CASE(
    "a triggered node publishes one silhouette per trigger edge, showing that trigger's frame") {
  const fs::path dir =
      fs::temp_directory_path() / ("hullpose_test_node_trigger_" + std::to_string(::getpid()));
  test::write_dataset(dir, test::small_synth({64, 48}, 1, 1, 1), 0);  // the rig file
  for (int k = 0; k < kRecorded; ++k)
    cv::imwrite(test::indexed(dir / "cam0", "seq", k), frame_mask(k));
  const std::string wire = (dir / "wire.sock").string();
  const int offset_ms = GENERATE(0, 2000);  // a board whose clock is 2 s off labels frames the same
  std::ofstream(dir / "node.yaml")
      << "%YAML:1.0\ncamera_id: 0\nrig_file: rig.yaml\n"
      << "source: { type: file, path: cam0/seq_%06d.png }\n"
      << "bgs: { method: threshold, learn_frames: 1 }\n"
      << "post: { open_radius: 0, close_radius: 0, min_blob_area: 0, max_hole_area: 0 }\n"
      << "lcm: { url: \"" << kUrl << "\", queue_depth: 16 }\n"
      << "trigger: { edges: wire, path: wire.sock, clock_offset_ms: " << offset_ms << " }\n";

  // The test's own bus (a listener elsewhere on the network), the master's and the node's are
  // three handles on one multicast group, as three processes of the rig would be.
  const auto bus = bus::open_bus(kUrl);
  Received got;
  // Handled only after the run: keep every silhouette (LCM keeps 30 per subscription by default).
  const auto sub = bus->subscribe(
      "SILHOUETTE",
      [&got](std::span<const uint8_t> b, const std::string&) { got.on_silhouette(b); },
      10 * kPulses);

  // The master waits for the node's wire connection (made at the end of node.start()), then pulses.
  sync::TriggerMasterConfig mc;
  mc.rig_id = "test-rig";
  mc.rate_hz =
      20;  // slow enough that a loaded test machine's scheduling stays well inside a period
  auto line = sync::open_trigger_line("wire:" + wire);
  const auto master_bus = bus::open_bus(kUrl);
  sync::TriggerMaster master(
      mc, *line, system_clock(),
      [&](const hullpose_msg::trigger_t& t) { wire::publish(*master_bus, "TRIGGER", t); },
      sync::new_epoch());
  size_t connected = 0;
  std::thread master_thread([&] {
    connected = line->wait_for_nodes(1, 20'000);
    for (int i = 0; connected == 1 && i < kPulses; ++i) master.pulse();
  });

  const NodeConfig config = load_node_config(dir / "node.yaml");
  const auto node_bus = open_node_bus(config);
  CameraNode node(config, *node_bus);
  node.start();
  std::atomic<bool> stop{false};
  std::thread node_thread([&] { node.run(stop); });
  master_thread.join();
  // Every pulse's silhouette arrives (bounded wait for the network, not a timing assumption).
  const auto done = [&] {
    return !got.by_seq.empty() && got.by_seq.rbegin()->first == kPulses - 1;
  };
  for (const int64_t until = monotonic_us() + 10'000'000; !done() && monotonic_us() < until;)
    bus->handle(25);
  stop = true;
  node_thread.join();
  node.stop();
  REQUIRE(connected == 1);

  // The node learns the clock offset from the first three announcements; the edges waiting for it
  // are mapped then. None is lost or duplicated.
  CHECK(got.duplicates == 0);
  REQUIRE(static_cast<int>(got.by_seq.size()) == kPulses);
  CHECK(got.by_seq.begin()->first == 0);
  CHECK(got.by_seq.rbegin()->first == kPulses - 1);
  cv::Mat decoded;
  for (const auto& [seq, m] : got.by_seq) {
    INFO("trigger " << seq << ", clock offset " << offset_ms << " ms");
    REQUIRE(decode_silhouette(m.payload, {}, decoded) == CodecError::kNone);
    CHECK(cv::countNonZero(decoded != frame_mask(static_cast<int>(seq))) == 0);
    // Times are on the master's clock, not the board's: a stamp left on the board's clock would
    // be the 2 s offset away. The bounds are half of that, so the scheduling of this loaded
    // machine (how late a thread reads the wire) is not what is asserted.
    CHECK(std::abs(m.capture_utime - m.utime) < 1'000'000);
    CHECK(m.node_done_utime >= m.capture_utime);
    CHECK(m.node_done_utime - m.utime < 1'000'000);
  }
  CHECK(node.counters().get("no_trigger") == 0);
  fs::remove_all(dir);
}
