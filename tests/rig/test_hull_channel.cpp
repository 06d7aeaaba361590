// The optional HULL channel (hull_t): the coarse hull's codec (every field of a hostile message
// refused by name), coarsening (any fine voxel occupies its coarse one), the publisher's rate and
// its drop-when-busy mailbox, and the fusion service with the channel off (nothing sent) and on.
// memq:// and a SimClock: no sockets, no sleeps.
#include <catch2/catch.hpp>
#include <hullpose_msg/hull_t.hpp>
#include <random>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/clock.hpp"
#include "hullpose/fusion_host/fusion_service.hpp"
#include "hullpose/fusion_host/hull_publisher.hpp"
#include "hullpose/msg/hull.hpp"
#include "hullpose/msg/wire.hpp"
#include "rig_fixtures.hpp"

using namespace hullpose;
using hullpose_msg::hull_t;

namespace {
// A 128 x 100 x 70 hull with a box "torso" and a one-voxel-thin "arm".
fusion::BitGrid test_hull(VoxelGridSpec& spec) {
  spec.dims = {128, 100, 70};
  spec.origin_mm = {-2000, -1500, 0};
  spec.voxel_mm = 31.25;
  fusion::BitGrid g(spec.dims);
  for (int z = 10; z < 50; ++z)
    for (int y = 40; y < 52; ++y)
      for (int x = 60; x < 75; ++x) g.set(x, y, z);
  for (int x = 75; x < 127; ++x) g.set(x, 45, 40);
  return g;
}

hull_t good_message() {
  VoxelGridSpec spec;
  const fusion::BitGrid fine = test_hull(spec);
  msg::CoarseHull coarse;
  std::vector<uint64_t> scratch;
  fusion::coarsen_hull(fine, spec, 64, coarse, scratch);
  coarse.utime = 1'700'000'000'000'000;
  coarse.trigger_seq = 9;
  SilhouetteEncoder enc;
  hull_t m;
  msg::to_message(coarse, "rigA", enc, m);
  return m;
}
}  // namespace

TEST_CASE("hull: coarsening keeps every occupied fine voxel's coarse voxel and nothing else") {
  VoxelGridSpec spec;
  const fusion::BitGrid fine = test_hull(spec);
  msg::CoarseHull c;
  std::vector<uint64_t> scratch;
  fusion::coarsen_hull(fine, spec, 64, c, scratch);
  CHECK(c.dims == std::array<int, 3>{64, 50, 35});  // factor 2
  CHECK(c.voxel_mm == 62.5f);
  CHECK(c.carved_voxel_mm == 31.25f);
  int expected = 0;
  for (int z = 0; z < 35; ++z)
    for (int y = 0; y < 50; ++y)
      for (int x = 0; x < 64; ++x) {
        bool any = false;
        for (int k = 0; k < 8; ++k)
          any = any || fine.get_or_zero(2 * x + (k & 1), 2 * y + (k >> 1 & 1), 2 * z + (k >> 2));
        expected += any;
        REQUIRE(c.occupied(x, y, z) == any);
      }
  CHECK(c.num_occupied == expected);
  CHECK(c.occupied(63, 22, 20));  // the thin arm survives
  fusion::coarsen_hull(fine, spec, 32, c, scratch);
  CHECK(c.dims == std::array<int, 3>{32, 25, 18});  // factor 4, rounded up
}

TEST_CASE("hull: a message round-trips, is small, and every bad field is refused by name") {
  const hull_t m = good_message();
  CHECK(m.payload_size < 1500);  // 64 x 50 x 35 bits would be 14 000 bytes
  const auto bytes = testing::encode(m);
  hull_t d;
  REQUIRE(wire::decode(std::span<const uint8_t>(bytes), d));
  msg::CoarseHull c;
  REQUIRE(msg::from_message(d, c) == msg::HullError::kNone);
  CHECK(c.trigger_seq == 9);
  CHECK(c.num_occupied == m.num_occupied);
  CHECK(c.occupied(31, 22, 10));

  const auto refused = [](hull_t bad) {
    msg::CoarseHull out;
    return msg::from_message(bad, out);
  };
  using E = msg::HullError;
  for (int32_t n : {0, -1, 65, 1 << 30}) {
    hull_t b = m;
    b.nz = n;
    CHECK(refused(b) == E::kBadDims);
  }
  for (float v : {NAN, INFINITY, -1.f, 0.f, 1e9f}) {
    hull_t b = m;
    b.voxel_mm = v;
    CHECK(refused(b) == E::kBadGeometry);
    b = m;
    b.origin_mm[1] = v == 0.f || v == -1.f ? NAN : v;
    CHECK(refused(b) == E::kBadGeometry);
  }
  {
    hull_t b = m;
    b.carved_voxel_mm = b.voxel_mm * 2;
    CHECK(refused(b) == E::kBadGeometry);
    b = m;
    b.encoding = 7;
    CHECK(refused(b) == E::kBadEncoding);
    b = m;
    b.ny = m.ny - 1;  // the image is no longer ny*nz rows
    CHECK(refused(b) == E::kBadPayload);
    b = m;
    b.num_occupied = m.num_occupied + 1;
    CHECK(refused(b) == E::kBadCount);
    b = m;
    b.payload.resize(b.payload.size() / 2);
    b.payload_size = static_cast<int32_t>(b.payload.size());
    CHECK(refused(b) == E::kBadPayload);
  }
  // Wire level: truncations, trailing bytes, hostile payload lengths; random bytes never throw.
  for (size_t n = 0; n < bytes.size(); ++n)
    CHECK_FALSE(wire::decode(std::span<const uint8_t>(bytes.data(), n), d));
  std::mt19937 rng(16);
  for (int i = 0; i < 5000; ++i) {
    auto b = bytes;
    b[rng() % b.size()] = static_cast<uint8_t>(rng());
    if (wire::decode(std::span<const uint8_t>(b), d)) msg::from_message(d, c);  // no throw
  }
}

TEST_CASE("hull publisher: one per period of trigger time, a busy worker drops and counts") {
  const auto bus = bus::open_bus("memq://");
  Counters counters;
  std::vector<hull_t> got;
  hull_t rx;
  Counters rx_counters;
  const auto sub = wire::subscribe(
      *bus, "HULL", rx, rx_counters, "malformed_hull", [&](const hull_t& h) { got.push_back(h); },
      100);
  VoxelGridSpec spec;
  const fusion::BitGrid fine = test_hull(spec);
  fusion::HullPublishOptions o;
  o.rate_hz = 2;
  {
    fusion::HullPublisher pub(*bus, "rigA", o, counters);
    const int64_t t0 = 1'700'000'000'000'000;
    for (int64_t seq = 0; seq < 60; ++seq) {  // 2 s of a 30 Hz trigger
      pub.offer(fine, spec, t0 + seq * 33'333, seq);
      pub.drain();  // the worker keeps up: nothing dropped
    }
    while (bus->handle(0)) {
    }
    REQUIRE(got.size() == 4);
    for (size_t i = 0; i < got.size(); ++i)
      CHECK(got[i].trigger_seq == static_cast<int64_t>(15 * i));
    CHECK(counters.get("hull_published") == 4);
    CHECK(counters.get("hull_dropped_busy") == 0);
    // Offers that come faster than the worker: never more than one waits, the rest are counted.
    o.rate_hz = 30;
  }
  fusion::HullPublisher fast(*bus, "rigA", o, counters);
  for (int64_t seq = 0; seq < 200; ++seq) fast.offer(fine, spec, seq * 33'334, seq);
  fast.drain();
  CHECK(counters.get("hull_published") + counters.get("hull_dropped_busy") == 4 + 200);
  CHECK(rx_counters.get("malformed_hull") == 0);
  CHECK_THROWS(fusion::HullPublisher(*bus, "rigA", fusion::HullPublishOptions{}, counters));
}

TEST_CASE("fusion service: HULL is silent unless asked, then carries the pipeline's hull") {
  const Rig rig = testing::make_rig(2, 60, 40);
  VoxelGridSpec spec;
  const fusion::BitGrid fine = test_hull(spec);
  struct WithHull final : fusion::FramePipeline {
    const fusion::BitGrid* hull;
    const VoxelGridSpec* spec;
    void process(const fusion::AssembledFrame&, fusion::PoseEstimate& out) override {
      out.valid = true;
      out.hull = hull;
      out.hull_grid = spec;
    }
  } pipeline;
  pipeline.hull = &fine;
  pipeline.spec = &spec;
  for (const double rate : {0.0, 10.0}) {
    INFO("--hull-rate " << rate);
    const auto bus = bus::open_bus("memq://");
    SimClock clock;
    fusion::ServiceConfig cfg;
    cfg.assembler.min_cameras = 2;
    cfg.hull.rate_hz = rate;
    int hulls = 0, skeletons = 0;
    const auto h =
        bus->subscribe("HULL", [&](std::span<const uint8_t>, const std::string&) { ++hulls; });
    const auto s = bus->subscribe(
        "SKELETON", [&](std::span<const uint8_t>, const std::string&) { ++skeletons; });
    {
      fusion::FusionService service(*bus, clock, rig, pipeline, cfg);
      const int64_t t0 = clock.realtime_utime();
      for (int64_t seq = 0; seq < 9; ++seq) {
        for (int cam = 0; cam < 2; ++cam)
          wire::publish(*bus, "SILHOUETTE",
                        testing::make_silhouette(rig, cam, seq, t0 + seq * 33'333));
        for (int i = 0; i < 4; ++i) service.step(0);
        service.flush();  // drains the hull worker: deterministic counts
      }
      while (bus->handle(0)) {
      }
      CHECK(service.counters().get("hull_published") == (rate > 0 ? 3 : 0));
    }
    CHECK(skeletons == 9);
    CHECK(hulls == (rate > 0 ? 3 : 0));  // seq 0, 3, 6 at 10 Hz of a 30 Hz trigger
  }
}
