#include <poll.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "hullpose/camera_node/edge_source.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/firmware_sync/trigger_master.hpp"

using namespace hullpose::sync;
using hullpose::SimClock;

namespace {
struct Rig {
  SimClock clock;
  SimTriggerLine line;
  std::vector<hullpose_msg::trigger_t> sent;
  TriggerMaster master;
  explicit Rig(double hz = 30, int width = 1000)
      : master(
            {"rigA", hz, width}, line, clock,
            [this](const hullpose_msg::trigger_t& t) { sent.push_back(t); }, 77) {}
};
}  // namespace

TEST_CASE("trigger master pulses on an absolute schedule and announces every pulse") {
  Rig r(30);
  for (int i = 0; i < 10; ++i) CHECK(r.master.pulse() == i);
  REQUIRE(r.sent.size() == 10);
  for (size_t i = 0; i < r.sent.size(); ++i) {
    CHECK(r.sent[i].seq == static_cast<int64_t>(i));
    CHECK(r.sent[i].epoch == 77);
    CHECK(r.sent[i].rig_id == "rigA");
    CHECK(r.sent[i].period_us == 33333);
    CHECK(r.sent[i].pulse_width_us == 1000);
    if (i > 0) CHECK(r.sent[i].utime - r.sent[i - 1].utime == 33333);
  }
  REQUIRE(r.line.levels().size() == 20);
  for (size_t i = 0; i < 20; ++i) CHECK(r.line.levels()[i] == (i % 2 == 0));
  CHECK(r.master.jitter().max_us() == 0);
  CHECK(r.master.missed_slots() == 0);
}

TEST_CASE("a late wake-up is measured as jitter and does not shift later pulses") {
  Rig r(100);
  r.master.pulse();
  r.clock.inject_lateness(700);
  r.master.pulse();
  r.master.pulse();
  CHECK(r.sent[1].utime - r.sent[0].utime == 10000 + 700);
  CHECK(r.sent[2].utime - r.sent[0].utime == 20000);  // back on the grid
  CHECK(r.master.jitter().max_us() == 700);
  CHECK(r.master.jitter().count() == 3);
  CHECK(r.master.jitter().p99_us() == 700);
}

TEST_CASE("an overrun skips whole slots and keeps the phase") {
  Rig r(100);
  r.master.pulse();         // edge at t0
  r.clock.advance(35'000);  // the process stalls for 3.5 periods
  r.master.pulse();
  CHECK(r.master.missed_slots() == 3);
  CHECK(r.sent[1].seq == 1);
  CHECK(r.sent[1].utime - r.sent[0].utime == 40'000);
}

TEST_CASE("rate change applies from the next pulse; stop and start keep seq and epoch") {
  Rig r(30);
  r.master.pulse();
  r.master.set_rate(60);
  r.master.pulse();
  r.master.pulse();
  CHECK(r.sent[2].period_us == 16667);
  CHECK(r.sent[2].utime - r.sent[1].utime == 16667);
  CHECK_THROWS_AS(r.master.set_rate(0), hullpose::Error);
  CHECK_THROWS_AS(r.master.set_rate(1e6), hullpose::Error);

  int calls = 0;
  r.master.stop();
  r.master.start();
  r.clock.advance(1'000'000);
  r.master.run([&] { return ++calls <= 4; });
  REQUIRE(r.sent.size() == 7);
  CHECK(r.sent[6].seq == 6);
  CHECK(r.sent[6].epoch == 77);
  CHECK(r.master.missed_slots() == 0);  // a restarted train is scheduled from now
}

TEST_CASE("bad configuration and absent GPIO chips fail clearly") {
  SimClock clock;
  SimTriggerLine line;
  auto make = [&](TriggerMasterConfig c) {
    TriggerMaster m(
        c, line, clock, [](const hullpose_msg::trigger_t&) {}, 1);
  };
  CHECK_THROWS_WITH(make({"", 30, 1000}), Catch::Contains("rig_id"));
  CHECK_THROWS_WITH(make({"r", -5, 1000}), Catch::Contains("rate"));
  CHECK_THROWS_WITH(make({"r", 30, 40000}), Catch::Contains("pulse width"));
  CHECK_THROWS_WITH(
      open_trigger_line("gpiod:hullpose-no-such-chip:3"),
      Catch::Contains("hullpose-no-such-chip") && Catch::Contains("cannot open GPIO chip"));
  CHECK_THROWS_WITH(open_trigger_line("gpiod:chip:x"), Catch::Contains("not a line number"));
  CHECK_THROWS_WITH(open_trigger_line("usb"), Catch::Contains("expected"));
  CHECK_THROWS_WITH(hullpose::trigger::open_edge_source("gpiod:hullpose-no-such-chip:3", {}),
                    Catch::Contains("cannot open GPIO chip"));
  CHECK_THROWS_WITH(hullpose::trigger::open_edge_source("wire:/nonexistent/hullpose.sock", {}),
                    Catch::Contains("cannot connect"));
  CHECK(new_epoch() > 0);
}

TEST_CASE("the simulated wire carries kernel-style edge stamps to every connected node") {
  const std::string path = "/tmp/hullpose-test-wire-" + std::to_string(::getpid());
  auto line = open_trigger_line("wire:" + path);
  hullpose::trigger::NodeClock skewed{2'000'000};
  auto a = hullpose::trigger::open_edge_source("wire:" + path, {});
  auto b = hullpose::trigger::open_edge_source("wire:" + path, skewed);
  const int64_t before = hullpose::monotonic_us();
  const int64_t first = line->set(true);  // the stamp it sent, for the master's announcement
  CHECK(line->set(false) == -1);
  line->set(true);
  const int64_t after = hullpose::monotonic_us();
  for (auto* src : {a.get(), b.get()}) {
    pollfd p{src->fd(), POLLIN, 0};
    REQUIRE(::poll(&p, 1, 5000) == 1);
    int64_t e1 = 0, e2 = 0;
    REQUIRE(src->read(e1));
    REQUIRE(::poll(&p, 1, 5000) == 1);
    REQUIRE(src->read(e2));
    const int64_t skew = src == b.get() ? 2'000'000 : 0;
    CHECK(e1 - skew >= before);
    CHECK(e1 - skew == first);
    CHECK(e2 - skew <= after);
    CHECK(e2 >= e1);
    int64_t none = 0;
    CHECK_FALSE(src->read(none));
  }
  line.reset();  // the master goes away: the node notices and does not crash
  int64_t e = 0;
  CHECK_FALSE(a->read(e));
}
