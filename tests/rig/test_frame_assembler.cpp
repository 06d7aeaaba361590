#include <catch2/catch.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <random>
#include <vector>

#include "hullpose/common/check.hpp"
#include "hullpose/fusion_host/frame_assembler.hpp"
#include "rig_fixtures.hpp"

using namespace hullpose;
using namespace hullpose::fusion;
using hullpose::testing::encode;
using hullpose::testing::make_rig;
using hullpose::testing::make_silhouette;

namespace {
constexpr int64_t kT0 = 1'700'000'000'000'000;
constexpr int64_t kP = 33'333;

struct Closed {
  int64_t seq;
  FrameStatus status;
  std::vector<int> cams;
  uint64_t mask;
  bool masks_match;  // every view's mask is the one sent for this seq
};

struct Harness {
  Rig rig;
  std::vector<Closed> closed;
  FrameAssembler fa;
  Harness(int n, AssemblerConfig cfg)
      : rig(make_rig(n)), fa(rig, cfg, [this](const AssembledFrame& f) { record(f); }) {}
  void record(const AssembledFrame& f) {
    Closed c{f.trigger_seq, f.status, {}, f.camera_mask, true};
    for (const View& v : f.views) {
      c.cams.push_back(v.camera_id);
      cv::Mat expect;
      decode_silhouette(make_silhouette(rig, v.camera_id, f.trigger_seq, f.utime).payload, {},
                        expect);
      if (v.mask->size() != expect.size() || cv::countNonZero(*v.mask != expect) != 0)
        c.masks_match = false;
      if (v.capture_utime != f.utime + 300) c.masks_match = false;
    }
    closed.push_back(c);
  }
  void send(int cam, int64_t seq, int64_t now) {
    fa.on_bytes(encode(make_silhouette(rig, cam, seq, kT0 + seq * kP)), kT0 + seq * kP + 9000, now);
  }
};
}  // namespace

TEST_CASE("all cameras arrived: the frame closes at once with every view") {
  Harness h(4, {});
  for (int cam : {2, 0, 3, 1}) h.send(cam, 7, 100);
  REQUIRE(h.closed.size() == 1);
  CHECK(h.closed[0].seq == 7);
  CHECK(h.closed[0].status == FrameStatus::kComplete);
  CHECK(h.closed[0].cams == std::vector<int>{0, 1, 2, 3});
  CHECK(h.closed[0].mask == 0xF);
  CHECK(h.closed[0].masks_match);
  CHECK(h.fa.counters().get("fused_complete") == 1);
  CHECK(h.fa.open_frames() == 0);
}

TEST_CASE("deadline from the first arrival: fuse with min_cameras, later ones are late") {
  AssemblerConfig cfg;
  cfg.min_cameras = 2;
  cfg.deadline_us = 30'000;
  Harness h(4, cfg);
  h.send(0, 1, 1000);
  h.send(1, 1, 5000);
  h.send(3, 1, 9000);
  h.fa.poll(30'999);
  CHECK(h.closed.empty());
  h.fa.poll(31'000);
  REQUIRE(h.closed.size() == 1);
  CHECK(h.closed[0].status == FrameStatus::kPartial);
  CHECK(h.closed[0].cams == std::vector<int>{0, 1, 3});
  CHECK(h.closed[0].mask == 0b1011);
  h.send(2, 1, 40'000);
  CHECK(h.fa.counters().get("late") == 1);
  CHECK(h.closed.size() == 1);
}

TEST_CASE("too few cameras at the deadline is closed as such and counted") {
  AssemblerConfig cfg;
  cfg.min_cameras = 3;
  Harness h(4, cfg);
  h.send(0, 1, 0);
  h.send(1, 1, 0);
  h.fa.poll(1'000'000);
  REQUIRE(h.closed.size() == 1);
  CHECK(h.closed[0].status == FrameStatus::kTooFew);
  CHECK(h.closed[0].cams.size() == 2);
  CHECK(h.fa.counters().get("too_few_cameras") == 1);
}

TEST_CASE("interleaved sequences are never mixed, and close in order") {
  AssemblerConfig cfg;
  cfg.min_cameras = 1;
  Harness h(3, cfg);
  h.send(0, 10, 0);
  h.send(0, 11, 1);
  h.send(1, 11, 2);
  h.send(1, 10, 3);
  h.send(0, 12, 4);
  h.send(2, 11, 5);  // 11 complete: 10 is closed first, with what it has
  REQUIRE(h.closed.size() == 2);
  CHECK(h.closed[0].seq == 10);
  CHECK(h.closed[0].status == FrameStatus::kPartial);
  CHECK(h.closed[0].cams == std::vector<int>{0, 1});
  CHECK(h.closed[1].seq == 11);
  CHECK(h.closed[1].status == FrameStatus::kComplete);
  for (const auto& c : h.closed) CHECK(c.masks_match);
  h.send(2, 10, 6);  // straggler of a closed frame
  CHECK(h.fa.counters().get("late") == 1);
  h.fa.flush();
  REQUIRE(h.closed.size() == 3);
  CHECK(h.closed[2].seq == 12);
}

TEST_CASE(
    "duplicate, foreign, unknown, wrong-size and inconsistent messages are counted and dropped") {
  AssemblerConfig cfg;
  cfg.min_cameras = 1;
  Harness h(2, cfg);
  const int64_t u = kT0 + 5 * kP;
  h.send(0, 5, 0);
  h.send(0, 5, 1);
  CHECK(h.fa.counters().get("duplicate") == 1);

  auto bad = [&](auto mutate, const char* reason) {
    auto m = make_silhouette(h.rig, 1, 5, u);
    mutate(m);
    const int64_t before = h.fa.counters().get(reason);
    h.fa.on_silhouette(m, u, 2);
    INFO(reason);
    CHECK(h.fa.counters().get(reason) == before + 1);
  };
  bad([](auto& m) { m.rig_id = "otherRig"; }, "foreign_rig");
  bad([](auto& m) { m.camera_id = 9; }, "unknown_camera");
  bad([](auto& m) { m.camera_id = -1; }, "unknown_camera");
  bad([](auto& m) { m.width = 640; }, "wrong_size");
  bad([](auto& m) { m.encoding = 7; }, "bad_encoding");
  bad([](auto& m) { m.payload_size += 1; }, "bad_fields");
  bad([](auto& m) { m.roi_x += 1; }, "bad_fields");
  bad([](auto& m) { m.trigger_seq = -3; }, "bad_fields");
  bad([](auto& m) { m.utime += 50'000; }, "inconsistent_utime");
  bad([](auto& m) { m.utime += 5'000'000; }, "implausible_time");
  bad([](auto& m) { m.payload[0] = 'X'; }, "decode_error");
  bad(
      [](auto& m) {
        m.payload.pop_back();
        m.payload_size -= 1;
      },
      "decode_error");
  bad(
      [](auto& m) {
        m.payload[4] = 0xFF;
        m.payload[5] = 0xFF;
      },
      "decode_error");  // width 65535 > camera
  REQUIRE(h.closed.empty());
  h.send(1, 5, 3);  // the real one still completes the frame
  REQUIRE(h.closed.size() == 1);
  CHECK(h.closed[0].status == FrameStatus::kComplete);
  CHECK(h.closed[0].masks_match);
}

TEST_CASE("hostile bytes on the silhouette channel never crash or allocate wildly") {
  Harness h(2, {});
  std::mt19937 rng(42);
  const auto valid = encode(make_silhouette(h.rig, 0, 3, kT0));
  int64_t sent = 0;
  for (int i = 0; i < 3000; ++i) {
    std::vector<uint8_t> b;
    switch (i % 4) {
      case 0:  // random bytes
        b.resize(rng() % 200);
        for (auto& x : b) x = static_cast<uint8_t>(rng());
        break;
      case 1:  // truncated
        b.assign(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(rng() % valid.size()));
        break;
      case 2: {  // a valid message with one length field set to a hostile value
        b = valid;
        const int32_t hostile[] = {0, -1, -100000, 0x7fffffff, 1 << 24};
        const int32_t v = hostile[rng() % 5];
        const size_t rig_len_at = 16,
                     payload_len_at = valid.size() - 24 -
                                      static_cast<size_t>(valid.size() - 24 - 16 - 4 - 5 - 4 - 8 -
                                                          8 - 24 - 1 - 4) +
                                      0;
        (void)payload_len_at;
        const size_t at = (rng() % 2)
                              ? rig_len_at
                              : 16 + 4 + 5 + 4 + 8 + 8 + 24 + 1;  // rig_id length / payload_size
        for (int k = 0; k < 4; ++k)
          b[at + static_cast<size_t>(k)] =
              static_cast<uint8_t>(static_cast<uint32_t>(v) >> (24 - 8 * k));
        break;
      }
      default:  // random flips in a valid message
        b = valid;
        for (int f = 0; f < 3; ++f) b[rng() % b.size()] = static_cast<uint8_t>(rng());
    }
    h.fa.on_bytes(b, kT0, i);
    ++sent;
  }
  h.fa.flush();
  const auto& c = h.fa.counters();
  const int64_t dropped = c.get("malformed_lcm") + c.get("decode_error") + c.get("foreign_rig") +
                          c.get("unknown_camera") + c.get("wrong_size") + c.get("bad_fields") +
                          c.get("bad_encoding") + c.get("duplicate") + c.get("late") +
                          c.get("inconsistent_utime") + c.get("implausible_time");
  CHECK(c.get("malformed_lcm") > 1500);
  // Every message is either dropped with a reason or accepted into a frame.
  int64_t accepted = 0;
  for (const auto& f : h.closed) accepted += static_cast<int64_t>(f.cams.size());
  CHECK(dropped + accepted == sent);
}

TEST_CASE("open frames are capped: memory stays bounded under a flood of sequences") {
  AssemblerConfig cfg;
  cfg.max_open = 4;
  cfg.min_cameras = 2;
  Harness h(3, cfg);
  for (int64_t s = 0; s < 1000; ++s) {
    h.send(static_cast<int>(s % 3), s, s);
    CHECK(h.fa.open_frames() <= 4);
  }
  CHECK(h.fa.counters().get("capacity") == 996);
  CHECK(h.fa.counters().get("too_few_cameras") == 996);
  h.send(0, 2, 2000);  // long gone
  CHECK(h.fa.counters().get("late") == 1);
}

TEST_CASE(
    "trigger announcements account for frames no silhouette reached; deadline from the trigger") {
  AssemblerConfig cfg;
  cfg.min_cameras = 1;
  cfg.deadline_from = DeadlineFrom::kTrigger;
  cfg.deadline_us = 50'000;
  cfg.no_views_timeout_us = 100'000;
  Harness h(2, cfg);
  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  t.period_us = static_cast<int32_t>(kP);
  t.epoch = 3;
  for (int64_t s = 0; s < 3; ++s) {
    t.seq = s;
    t.utime = kT0 + s * kP;
    h.fa.on_trigger(t, s * kP);
  }
  h.send(0, 1, kP + 20'000);  // seq 1: one view, deadline 50 ms after its trigger arrived
  h.fa.poll(kP + 49'999);
  CHECK(h.closed.empty());
  h.fa.poll(kP + 50'000);  // seq 1 is due; seq 0 (older) closes first
  REQUIRE(h.closed.size() == 2);
  CHECK(h.closed[0].seq == 0);
  CHECK(h.closed[0].status == FrameStatus::kTooFew);
  CHECK(h.closed[0].cams.empty());
  CHECK(h.closed[1].seq == 1);
  CHECK(h.closed[1].status == FrameStatus::kPartial);
  h.fa.poll(2 * kP + 100'000);
  REQUIRE(h.closed.size() == 3);
  CHECK(h.fa.counters().get("no_views") == 2);
  t.rig_id = "x";
  h.fa.on_trigger(t, 0);
  CHECK(h.fa.counters().get("foreign_rig_trigger") == 1);
}

TEST_CASE("while announcements flow, a silhouette must fit the trigger stream") {
  AssemblerConfig cfg;
  cfg.min_cameras = 1;
  Harness h(2, cfg);
  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  t.period_us = static_cast<int32_t>(kP);
  t.epoch = 3;
  t.seq = 100;
  t.utime = kT0 + 100 * kP;
  h.fa.on_trigger(t, 0);
  auto send_at = [&](int64_t seq, int64_t utime) {
    auto m = make_silhouette(h.rig, 0, seq, utime);
    h.fa.on_silhouette(m, utime, 10);
  };
  send_at(99, kT0 + 99 * kP);        // fits
  send_at(100'000, kT0 + 100 * kP);  // a flipped sequence number
  send_at(101, kT0 + 99 * kP);       // a newer sequence at an older time
  send_at(100, kT0 + 101 * kP);      // an announced sequence at another time
  send_at(102, kT0 + 110 * kP);      // too far after the newest trigger
  send_at(300, kT0 + 300 * kP);      // far ahead of the newest trigger
  CHECK(h.fa.counters().get("implausible_time") == 5);
  h.fa.flush();
  REQUIRE(h.closed.size() == 2);  // 99 and the trigger-only 100
  CHECK(h.closed[0].seq == 99);
  CHECK(h.closed[0].cams == std::vector<int>{0});
}

TEST_CASE("a restarted master (sequence back to 0, newer time) is followed") {
  AssemblerConfig cfg;
  cfg.min_cameras = 1;
  Harness h(1, cfg);
  h.send(0, 500, 0);
  auto m = make_silhouette(h.rig, 0, 0, kT0 + 600 * kP);
  h.fa.on_silhouette(m, m.utime, 1);
  REQUIRE(h.closed.size() == 2);
  CHECK(h.closed[1].seq == 0);
  CHECK(h.fa.counters().get("seq_restart") == 1);
  auto old = make_silhouette(h.rig, 0, 3, kT0 + 3 * kP);  // old seq, old time: late
  h.fa.on_silhouette(old, old.utime, 2);
  CHECK(h.fa.counters().get("late") == 1);
  // An old sequence whose time is only a little newer is a bad message, not a restart.
  auto bumped = make_silhouette(h.rig, 0, 0, kT0 + 600 * kP + 200);
  h.fa.on_silhouette(bumped, bumped.utime, 3);
  CHECK(h.fa.counters().get("late") == 2);
  CHECK(h.fa.counters().get("seq_restart") == 1);
  CHECK(h.closed.size() == 2);
}

TEST_CASE(
    "a master restart seen on TRIGGER (new epoch) closes the old run's frames and follows the new "
    "one") {
  AssemblerConfig cfg;
  cfg.min_cameras = 1;
  Harness h(2, cfg);
  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  t.period_us = static_cast<int32_t>(kP);
  t.epoch = 1;
  for (int64_t s = 0; s < 60; ++s) {
    t.seq = s;
    t.utime = kT0 + s * kP;
    h.fa.on_trigger(t, s * kP);
    h.send(0, s, s * kP + 1);
    h.send(1, s, s * kP + 2);
  }
  h.send(0, 60, 61 * kP);  // seq 60 open with one view when the master restarts
  const int64_t restart = kT0 + 60 * kP + 100'000;  // quickly: 100 ms later, sequences from 0
  t.epoch = 2;
  for (int64_t s = 0; s < 5; ++s) {
    t.seq = s;
    t.utime = restart + s * kP;
    h.fa.on_trigger(t, 70 * kP + s * kP);
    auto m0 = make_silhouette(h.rig, 0, s, t.utime), m1 = make_silhouette(h.rig, 1, s, t.utime);
    h.fa.on_silhouette(m0, t.utime, 70 * kP + s * kP + 1);
    h.fa.on_silhouette(m1, t.utime, 70 * kP + s * kP + 2);
  }
  t.epoch = 1;  // a straggler announcement of the old run
  t.seq = 61;
  h.fa.on_trigger(t, 80 * kP);
  REQUIRE(h.closed.size() == 66);
  CHECK(h.closed[60].seq == 60);
  CHECK(h.closed[60].status == FrameStatus::kPartial);
  for (int64_t s = 0; s < 5; ++s) {
    CHECK(h.closed[static_cast<size_t>(61 + s)].seq == s);
    CHECK(h.closed[static_cast<size_t>(61 + s)].status == FrameStatus::kComplete);
  }
  CHECK(h.fa.counters().get("epoch_change") == 1);
  CHECK(h.fa.counters().get("stale_epoch_trigger") == 1);
  CHECK(h.fa.counters().get("late") == 0);
}

TEST_CASE("bad assembler configuration fails clearly") {
  const Rig rig = make_rig(4);
  auto make = [&](AssemblerConfig c) { FrameAssembler fa(rig, c, [](const AssembledFrame&) {}); };
  AssemblerConfig c;
  c.min_cameras = 5;
  CHECK_THROWS_WITH(make(c), Catch::Contains("min_cameras"));
  c = {};
  c.deadline_us = 0;
  CHECK_THROWS_WITH(make(c), Catch::Contains("deadline"));
  c = {};
  c.max_open = 0;
  CHECK_THROWS_WITH(make(c), Catch::Contains("max_open"));
  FrameAssembler fa(rig, {}, [](const AssembledFrame&) {});
  CHECK(fa.min_cameras() == 2);
}
