// The trigger listener against simulated edges, announcements and clocks: every scenario of
// issue 7 (late start, missed edges, lost / reordered / delayed announcements, clock offset,
// master restart) must label every edge correctly or drop it with a reason — never mislabel.
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "hullpose/camera_node/trigger_client.hpp"
#include "hullpose/camera_node/trigger_listener.hpp"
#include "hullpose/common/bus.hpp"
#include "hullpose/common/clock.hpp"
#include "hullpose/msg/wire.hpp"

using namespace hullpose::trigger;

namespace {
constexpr int64_t kPeriod = 33'333;
constexpr int64_t kMasterStart = 1'700'000'000'000'000;

// A pulse train and what one node sees of it. Node clock = master clock + offset.
struct Scenario {
  int64_t offset_us = 0;
  int64_t first_seq = 0;
  int pulses = 200;
  int64_t epoch = 11;
  double edge_loss = 0, announcement_loss = 0;
  int reorder_window = 1;    // shuffle announcement delivery within windows of this size
  double slow_fraction = 0;  // announcements delayed by 1.5 periods
  uint32_t seed = 1;
};

struct Event {
  int64_t at;  // node clock
  bool is_edge;
  int64_t edge_us;
  Announcement a;
};

struct Result {
  std::vector<MappedEdge> mapped;
  std::vector<int64_t> true_seq_of_edge;  // by edge time
  SequenceMapper mapper;
};

std::vector<Event> make_events(const Scenario& s, std::vector<std::pair<int64_t, int64_t>>& truth) {
  std::mt19937 rng(s.seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_int_distribution<int> latency(300, 4000), jitter(-20, 20);
  std::vector<Event> events;
  std::vector<Event> anns;
  for (int k = 0; k < s.pulses; ++k) {
    const int64_t seq = s.first_seq + k;
    const int64_t utime = kMasterStart + seq * kPeriod;
    const int64_t edge = utime + s.offset_us + jitter(rng);
    if (u(rng) >= s.edge_loss) {
      events.push_back({edge, true, edge, {}});
      truth.emplace_back(edge, seq);
    }
    if (u(rng) >= s.announcement_loss) {
      int64_t lat = latency(rng);
      if (u(rng) < s.slow_fraction) lat += kPeriod * 3 / 2;
      anns.push_back({edge + lat, false, 0, {seq, utime, s.epoch, kPeriod, edge + lat}});
    }
  }
  // Reordering: deliver announcements of a window in shuffled order.
  for (size_t i = 0; i + 1 < anns.size(); i += static_cast<size_t>(s.reorder_window)) {
    const size_t end = std::min(anns.size(), i + static_cast<size_t>(s.reorder_window));
    std::vector<int64_t> times;
    for (size_t j = i; j < end; ++j) times.push_back(anns[j].at);
    std::shuffle(anns.begin() + static_cast<std::ptrdiff_t>(i),
                 anns.begin() + static_cast<std::ptrdiff_t>(end), rng);
    std::sort(times.begin(), times.end());
    for (size_t j = i; j < end; ++j) {
      anns[j].at = times[j - i];
      anns[j].a.received_us = times[j - i];
    }
  }
  events.insert(events.end(), anns.begin(), anns.end());
  std::stable_sort(events.begin(), events.end(),
                   [](const Event& a, const Event& b) { return a.at < b.at; });
  return events;
}

// Feeds the events in arrival order, polling after each, then flushes.
void run(SequenceMapper& m, const std::vector<Event>& events, std::vector<MappedEdge>& out) {
  for (const Event& e : events) {
    if (e.is_edge)
      m.on_edge(e.edge_us);
    else
      m.on_announcement(e.a);
    m.poll(e.at, out);
  }
  if (!events.empty()) m.poll(events.back().at + 10'000'000, out);
}

// Every mapped edge has its true sequence; returns how many edges were mapped.
size_t check_all_correct(const std::vector<MappedEdge>& out,
                         const std::vector<std::pair<int64_t, int64_t>>& truth,
                         int64_t utime_of_seq0 = kMasterStart) {
  int64_t last = -1;
  for (const MappedEdge& e : out) {
    auto it = std::find_if(truth.begin(), truth.end(),
                           [&](const auto& t) { return t.first == e.edge_us; });
    REQUIRE(it != truth.end());
    CHECK(e.seq == it->second);
    CHECK(e.utime == utime_of_seq0 + e.seq * kPeriod);
    CHECK(e.seq > last);  // each sequence at most once, in order
    last = e.seq;
  }
  return out.size();
}
}  // namespace

TEST_CASE("clock offsets of +-2 s between boards: every edge gets the master's sequence") {
  for (int64_t offset : {int64_t{2'000'000}, int64_t{-2'000'000}, int64_t{0}, int64_t{12'345}}) {
    Scenario s;
    s.offset_us = offset;
    std::vector<std::pair<int64_t, int64_t>> truth;
    SequenceMapper m;
    std::vector<MappedEdge> out;
    run(m, make_events(s, truth), out);
    CHECK(check_all_correct(out, truth) == truth.size());
    REQUIRE(m.synced());
    CHECK(std::llabs(m.offset_us() - offset) < 100);
    CHECK(m.counters().total() == 0);
  }
}

TEST_CASE("a node started late joins with the right sequence numbers") {
  Scenario s;
  s.first_seq = 9000;
  s.offset_us = 2'000'000;
  std::vector<std::pair<int64_t, int64_t>> truth;
  auto events = make_events(s, truth);
  // The node comes up 37 events into the stream: it saw nothing before.
  events.erase(events.begin(), events.begin() + 37);
  truth.erase(std::remove_if(truth.begin(), truth.end(),
                             [&](const auto& t) { return t.first < events.front().at; }),
              truth.end());
  SequenceMapper m;
  std::vector<MappedEdge> out;
  run(m, events, out);
  CHECK(check_all_correct(out, truth) >= truth.size() - 1);
  CHECK(out.front().seq >= 9000 + 18);
}

TEST_CASE("missed edges leave gaps but never shift the labels") {
  Scenario s;
  s.edge_loss = 0.2;
  s.offset_us = -2'000'000;
  s.seed = 5;
  std::vector<std::pair<int64_t, int64_t>> truth;
  SequenceMapper m;
  std::vector<MappedEdge> out;
  run(m, make_events(s, truth), out);
  CHECK(check_all_correct(out, truth) == truth.size());
  CHECK(truth.size() < 180);
}

TEST_CASE("lost announcements are interpolated, reordered ones still match") {
  Scenario s;
  s.announcement_loss = 0.25;
  s.reorder_window = 3;
  s.offset_us = 2'000'000;
  s.seed = 9;
  std::vector<std::pair<int64_t, int64_t>> truth;
  SequenceMapper m;
  std::vector<MappedEdge> out;
  run(m, make_events(s, truth), out);
  const size_t n = check_all_correct(out, truth);
  CHECK(n >= truth.size() - 3);  // at most the edges after the last announcement
  CHECK(m.counters().get("interpolated") > 20);
  CHECK(std::count_if(out.begin(), out.end(), [](const MappedEdge& e) { return e.interpolated; }) ==
        m.counters().get("interpolated"));
}

TEST_CASE("a minority of announcements delayed by more than a period does not move the offset") {
  Scenario s;
  s.slow_fraction = 0.2;
  s.offset_us = 2'000'000;
  s.seed = 3;
  std::vector<std::pair<int64_t, int64_t>> truth;
  SequenceMapper m;
  std::vector<MappedEdge> out;
  run(m, make_events(s, truth), out);
  CHECK(check_all_correct(out, truth) == truth.size());
  CHECK(std::llabs(m.offset_us() - 2'000'000) < 100);
}

TEST_CASE("a master restart (new epoch) resynchronises; stale announcements are ignored") {
  Scenario a;
  a.offset_us = 2'000'000;
  a.pulses = 60;
  std::vector<std::pair<int64_t, int64_t>> truth_a, truth_b;
  auto events = make_events(a, truth_a);
  // The restarted master counts from 0 again, with a new phase, 3 s later.
  Scenario b = a;
  b.epoch = 12;
  b.first_seq = 0;
  b.seed = 2;
  const int64_t shift = 3'000'000 + 7'000 + 60 * kPeriod;
  auto later = make_events(b, truth_b);
  for (auto& e : later) {
    e.at += shift;
    e.edge_us += shift;
    e.a.utime += shift;
    e.a.received_us += shift;
  }
  for (auto& t : truth_b) t.first += shift;
  Event stale = events.back();
  stale.is_edge = false;
  stale.a = {59, kMasterStart + 59 * kPeriod, 11, kPeriod, later[40].at};
  stale.at = later[40].at;
  later.insert(later.begin() + 41, stale);
  SequenceMapper m;
  std::vector<MappedEdge> out_a, out_b;
  run(m, events, out_a);
  check_all_correct(out_a, truth_a);
  run(m, later, out_b);
  CHECK(check_all_correct(out_b, truth_b, kMasterStart + shift) == truth_b.size());
  CHECK(m.epoch() == 12);
  CHECK(m.counters().get("epoch_change") == 1);
  CHECK(m.counters().get("stale_epoch") == 1);
}

TEST_CASE("no announcement across skipped master slots: the edge is dropped, not guessed") {
  SequenceMapper m;
  std::vector<MappedEdge> out;
  // Master pulses at slots 0..5, then overruns: seq 6 is at slot 8. The node sees every edge,
  // but the announcements of seq 5 and 6 are lost.
  const int64_t off = 2'000'000;
  auto slot = [](int s) { return kMasterStart + s * kPeriod; };
  const std::vector<std::pair<int, int>> pulses = {{0, 0}, {1, 1}, {2, 2}, {3, 3},
                                                   {4, 4}, {5, 5}, {6, 8}, {7, 9}};
  for (auto [seq, s] : pulses) {
    m.on_edge(slot(s) + off);
    if (seq != 5 && seq != 6) m.on_announcement({seq, slot(s), 11, kPeriod, slot(s) + off + 1000});
    m.poll(slot(s) + off + 1000, out);
  }
  m.poll(slot(20) + off, out);
  std::vector<int64_t> seqs;
  for (const auto& e : out) seqs.push_back(e.seq);
  CHECK(seqs == std::vector<int64_t>{0, 1, 2, 3, 4, 7});
  CHECK(m.counters().get("unmatched") == 2);
  CHECK(m.counters().get("interpolated") == 0);
}

TEST_CASE("glitches, hostile announcements and silence are counted, memory stays bounded") {
  SequenceMapper m;
  std::vector<MappedEdge> out;
  const int64_t off = 2'000'000;
  for (int k = 0; k < 10; ++k) {
    const int64_t u = kMasterStart + k * kPeriod;
    m.on_edge(u + off);
    if (k == 5) m.on_edge(u + off + 300);  // contact bounce
    m.on_announcement({k, u, 11, kPeriod, u + off + 800});
    m.on_announcement({k, u, 11, kPeriod, u + off + 900});  // duplicate
    m.poll(u + off + 1000, out);
  }
  m.on_announcement({1, 0, 11, 0, 0});  // zero period
  m.on_announcement({-4, 0, 11, kPeriod, 0});
  m.on_announcement({3, 0, 0, kPeriod, 0});         // no epoch
  m.on_announcement({3, 0, 11, 1'000'000'000, 0});  // a 1000 s period
  CHECK(out.size() == 10);
  CHECK(m.counters().get("duplicate_edge") == 1);
  CHECK(m.counters().get("duplicate_announcement") == 10);
  CHECK(m.counters().get("bad_announcement") == 4);

  SequenceMapper silent;
  for (int k = 0; k < 1000; ++k) silent.on_edge(k * kPeriod);
  silent.poll(2000 * kPeriod, out);
  CHECK(silent.counters().get("no_sync") + silent.counters().get("edge_overflow") == 1000);
  CHECK_FALSE(silent.synced());
}

TEST_CASE("externally triggered camera: the frame at each edge is tagged") {
  SimEdgeSource edges;
  ListenerConfig cfg;
  cfg.rig_id = "rigA";
  cfg.matcher.max_residual_us = 2000;
  TriggerListener listener(cfg, edges);
  std::vector<TaggedFrame> out;
  const int64_t off = 2'000'000;
  for (int k = 0; k < 20; ++k) {
    const int64_t u = kMasterStart + k * kPeriod;
    edges.push(u + off);
    hullpose_msg::trigger_t t{};
    t.utime = u;
    t.rig_id = k == 7 ? "otherRig" : "rigA";
    t.seq = k;
    t.period_us = kPeriod;
    t.epoch = 11;
    listener.on_announcement(t, u + off + 900);
    if (k == 7) {
      t.rig_id = "rigA";
      listener.on_announcement(t, u + off + 950);
    }
    listener.on_frame(100 + k, u + off + 250);  // exposure starts 250 us after the edge
    listener.poll(u + off + 1000, out);
  }
  listener.poll(kMasterStart + 30 * kPeriod + off, out);
  REQUIRE(out.size() == 20);
  for (int k = 0; k < 20; ++k) {
    CHECK(out[static_cast<size_t>(k)].frame_id == 100 + k);
    CHECK(out[static_cast<size_t>(k)].edge.seq == k);
    CHECK(out[static_cast<size_t>(k)].residual_us == 250);
    CHECK(out[static_cast<size_t>(k)].capture_utime() == kMasterStart + k * kPeriod + 250);
  }
  CHECK(listener.foreign_announcements() == 1);
}

TEST_CASE("simulated sensor: exactly one frame per edge, exposed just after it") {
  SimEdgeSource edges;
  ListenerConfig cfg;
  cfg.rig_id = "rigA";
  cfg.expose_after_edge_us = 200;
  TriggerListener listener(cfg, edges);
  std::vector<TaggedFrame> out;
  const int64_t off = -2'000'000;
  for (int k = 0; k < 20; ++k) {
    const int64_t u = kMasterStart + k * kPeriod;
    if (k != 9) edges.push(u + off);  // edge 9 never reached this board: no frame for it
    hullpose_msg::trigger_t t{};
    t.utime = u;
    t.rig_id = "rigA";
    t.seq = k;
    t.period_us = kPeriod;
    t.epoch = 11;
    listener.on_announcement(t, u + off + 900);
    listener.poll(u + off + 1000, out);
  }
  listener.poll(kMasterStart + 30 * kPeriod + off, out);
  REQUIRE(out.size() == 19);
  for (size_t i = 0; i < out.size(); ++i) {
    const int64_t k = static_cast<int64_t>(i < 9 ? i : i + 1);
    CHECK(out[i].edge.seq == k);
    CHECK(out[i].frame_id == static_cast<int64_t>(i));
    CHECK(out[i].residual_us == 200);
    CHECK(out[i].capture_utime() == kMasterStart + k * kPeriod + 200);
  }
}

TEST_CASE("free-running camera: the nearest frame to each edge, with its residual") {
  FrameMatcherConfig cfg;
  const int64_t frame_interval = 16'000;  // ~62.5 fps, not locked to the 30 Hz trigger
  cfg.max_residual_us = frame_interval / 2;
  FrameMatcher fm(cfg);
  std::vector<TaggedFrame> out;
  std::vector<int64_t> frames;
  for (int i = 0; i < 40; ++i) frames.push_back(5'000 + i * frame_interval);
  size_t next_frame = 0;
  for (int k = 0; k < 15; ++k) {
    const int64_t edge = 20'000 + k * kPeriod;
    MappedEdge e;
    e.edge_us = edge;
    e.seq = k;
    fm.on_edge(e);
    // Frames arrive as time passes; poll at each frame arrival.
    while (next_frame < frames.size() && frames[next_frame] <= edge + kPeriod) {
      fm.on_frame(static_cast<int64_t>(next_frame), frames[next_frame]);
      fm.poll(frames[next_frame], out);
      ++next_frame;
    }
  }
  fm.poll(1'000'000'000, out);
  REQUIRE(out.size() == 15);
  for (const auto& t : out) {
    int64_t best = frames[0];
    for (int64_t f : frames)
      if (std::llabs(f - t.edge.edge_us) < std::llabs(best - t.edge.edge_us)) best = f;
    CHECK(t.frame_us == best);
    CHECK(t.residual_us == best - t.edge.edge_us);
    CHECK(std::llabs(t.residual_us) <= frame_interval / 2);
  }
  // A camera that delivered nothing near an edge: the edge is dropped with a reason.
  MappedEdge lonely;
  lonely.edge_us = 5'000'000;
  fm.on_edge(lonely);
  fm.poll(6'000'000, out);
  CHECK(out.size() == 15);
  CHECK(fm.counters().get("no_frame") == 1);
}

TEST_CASE(
    "trigger client: TRIGGER over LCM + edges tag each externally triggered frame as it comes") {
  const auto bus = hullpose::bus::open_bus("memq://");
  hullpose::SimClock sim;
  SimEdgeSource edges;
  NodeClock clock{2'000'000, &sim};  // this board's clock is 2 s ahead
  ListenerConfig cfg;
  cfg.rig_id = "rigA";
  const auto set_node_now = [&](int64_t t) {
    sim.set_monotonic_us(t - clock.offset_us);
  };  // driven by the test
  TriggerClient client(*bus, edges, cfg, clock, "TRIGGER");
  const int64_t real_minus_mono = sim.realtime_minus_monotonic_us();
  const int64_t master0 = 1'700'000'000'000'000;
  const int64_t node_minus_master =
      5'000'000'000 + clock.offset_us;  // monotonic vs master epoch time
  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  t.period_us = static_cast<int32_t>(kPeriod);
  t.epoch = 9;
  int tagged = 0;
  for (int k = 0; k < 40; ++k) {
    t.seq = 1000 + k;
    t.utime = master0 + k * kPeriod;
    const int64_t edge_node = t.utime + node_minus_master;  // kernel stamp + board offset
    edges.push(edge_node);
    set_node_now(edge_node + 1200);  // the announcement arrives 1.2 ms after the edge
    hullpose::wire::publish(*bus, "TRIGGER", t);
    const uint8_t junk[] = {0, 1, 2};
    if (k == 3) bus->publish("TRIGGER", junk);
    // The sensor stamps exposure 300 us after the edge, on the node's realtime clock.
    const int64_t frame_utime = edge_node + 300 - clock.offset_us + real_minus_mono;
    auto tag = client.tag(k, frame_utime, 0);
    if (!tag) continue;
    ++tagged;
    CHECK(tag->frame_id == k);
    CHECK(tag->edge.seq == 1000 + k);
    CHECK(tag->edge.utime == t.utime);
    CHECK(tag->residual_us == 300);  // the test clock makes the mapping exact
    CHECK(tag->capture_utime() == t.utime + 300);
  }
  CHECK(tagged >= 36);  // the first frames come before the offset is learnt
  CHECK(client.counters().get("malformed_trigger") == 1);
}

TEST_CASE(
    "trigger client: a free-running camera's nearest frame to each edge is handed back once "
    "decided") {
  const auto bus = hullpose::bus::open_bus("memq://");
  hullpose::SimClock sim;
  SimEdgeSource edges;
  NodeClock clock{0, &sim};
  ListenerConfig cfg;
  cfg.rig_id = "rigA";
  const int64_t frame_interval = 16'000;  // ~62.5 fps, not locked to the trigger
  cfg.matcher.max_residual_us = frame_interval / 2;
  const auto set_node_now = [&](int64_t t) { sim.set_monotonic_us(t - clock.offset_us); };
  TriggerClient client(*bus, edges, cfg, clock, "TRIGGER");
  const int64_t real_minus_mono = sim.realtime_minus_monotonic_us();
  const int64_t master0 = 1'700'000'000'000'000, node_minus_master = 5'000'000'000;
  hullpose_msg::trigger_t t{};
  t.rig_id = "rigA";
  t.period_us = static_cast<int32_t>(kPeriod);
  t.epoch = 3;
  std::vector<int64_t> frames;  // node clock
  for (int i = 0; i < 100; ++i)
    frames.push_back(master0 + node_minus_master + 3'000 + i * frame_interval);
  std::vector<TaggedFrame> decided, all;
  int k = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    bool announced = false;
    for (; k < 40 && master0 + k * kPeriod + node_minus_master <= frames[i];
         ++k) {  // edges before this frame
      t.seq = 500 + k;
      t.utime = master0 + k * kPeriod;
      edges.push(t.utime + node_minus_master);
      hullpose::wire::publish(*bus, "TRIGGER", t);
      set_node_now(t.utime + node_minus_master + 1200);  // the announcement's arrival
      announced = true;
    }
    if (!announced) set_node_now(frames[i]);
    client.offer(static_cast<int64_t>(i), frames[i] + real_minus_mono, decided);
    for (const TaggedFrame& d : decided) {
      CHECK(d.frame_id <= static_cast<int64_t>(i));  // never a frame not seen yet
      all.push_back(d);
    }
  }
  REQUIRE(all.size() >= 30);  // the first edges come before the offset is learnt
  for (const TaggedFrame& d : all) {
    const int64_t edge = d.edge.edge_us;
    int64_t best = frames[0];
    for (int64_t f : frames)
      if (std::llabs(f - edge) < std::llabs(best - edge)) best = f;
    CHECK(d.frame_us == best);
    CHECK(std::llabs(d.residual_us) <= frame_interval / 2);
    CHECK(d.edge.seq == 500 + (d.edge.utime - master0) / kPeriod);
  }
}
