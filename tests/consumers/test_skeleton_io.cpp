// The consumers' shared layer: BVH skeleton (forward kinematics gives back the joints, Euler
// curves stay continuous, degenerate bones), humanoid map, gap filling, take reading (estimate
// CSV, lcm-logger log with malformed events and missing sequences, bad files), the drop-oldest
// queue and the live subscription (memq://).
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <random>
#include <sstream>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/msg/wire.hpp"
#include "hullpose/skeleton_io/bvh.hpp"
#include "hullpose/skeleton_io/drop_oldest_queue.hpp"
#include "hullpose/skeleton_io/gaps.hpp"
#include "hullpose/skeleton_io/humanoid.hpp"
#include "hullpose/skeleton_io/subscription.hpp"
#include "hullpose/skeleton_io/take.hpp"
#include "hullpose/synth/motion.hpp"

using namespace hullpose;
using namespace hullpose::skeleton_io;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("hullpose-test-skio-" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

double max_fk_error(const BvhSkeleton& s, const JointPositions& joints,
                    const std::vector<double>& channels) {
  std::vector<Eigen::Vector3d> pos;
  s.forward(channels, pos);
  double worst = 0;
  for (size_t n = 0; n < s.nodes().size(); ++n) {
    // A node sits on its joint (zero-length clavicle-like nodes on their parent's joint).
    worst = std::max(worst, (pos[n] - joints[static_cast<size_t>(s.nodes()[n].joint)]).norm());
  }
  return worst;
}

}  // namespace

TEST_CASE("BVH: forward kinematics of the solved channels gives back every joint") {
  for (const std::string motion : {"walk", "turn", "jump", "wave", "crouch"}) {
    const auto m = synth::make_builtin_motion(motion, {});
    JointPositions j0;
    m->sample(0, j0);
    const BvhSkeleton s(bone_lengths(j0));
    CHECK(s.num_channels() ==
          6 + 3 * static_cast<int>(std::count_if(s.nodes().begin() + 1, s.nodes().end(),
                                                 [](const auto& n) { return !n.end_site; })));
    std::vector<double> channels, previous;
    std::string line;
    double worst = 0, worst_text = 0, biggest_step = 0;
    for (int f = 0; f < 120; ++f) {
      JointPositions j;
      m->sample(f / 30.0, j);
      s.solve(j, channels);
      worst = std::max(worst, max_fk_error(s, j, channels));
      // What a file holds: six decimals.
      BvhSkeleton::format_line(channels, line);
      std::vector<double> parsed;
      std::istringstream in(line);
      for (double v; in >> v;) parsed.push_back(v);
      REQUIRE(parsed.size() == channels.size());
      worst_text = std::max(worst_text, max_fk_error(s, j, parsed));
      if (!previous.empty())
        for (size_t c = 3; c < channels.size(); ++c)
          biggest_step = std::max(biggest_step, std::abs(channels[c] - previous[c]));
      previous = channels;
    }
    INFO(motion);
    CHECK(worst < 1e-6);
    CHECK(worst_text < 0.01);
    CHECK(biggest_step < 90);  // unwrapped: no 360-degree jumps between frames at 30 Hz
  }
}

TEST_CASE(
    "BVH: limbs folded back onto their rest direction and zero-length bones stay exact or finite") {
  const auto m = synth::make_builtin_motion("tpose", {});
  JointPositions j;
  m->sample(0, j);
  const BvhSkeleton s(bone_lengths(j));
  // The left forearm turned back along the upper arm (opposite to its rest direction +X).
  JointPositions folded = j;
  const Eigen::Vector3d elbow = j[index(Joint::LElb)];
  for (Joint k : {Joint::LHand, Joint::LFTip}) {
    folded[static_cast<size_t>(index(k))] = elbow - (j[static_cast<size_t>(index(k))] - elbow);
  }
  std::vector<double> channels;
  s.solve(folded, channels);
  CHECK(max_fk_error(s, folded, channels) < 1e-6);
  // Every joint on one point: nothing to aim at, but the channels stay finite.
  JointPositions collapsed;
  collapsed.fill(Eigen::Vector3d(100, 200, 300));
  s.solve(collapsed, channels);
  for (double v : channels) CHECK(std::isfinite(v));
}

TEST_CASE("BVH: the hierarchy is the subject's: offsets are the median bone lengths, T-pose rest") {
  const auto m = synth::make_builtin_motion("walk", {});
  std::vector<SkeletonFrame> frames(5);
  for (size_t f = 0; f < frames.size(); ++f) {
    m->sample(static_cast<double>(f) / 30.0, frames[f].joints);
    frames[f].valid = f != 2;
  }
  frames[2].joints.fill(Eigen::Vector3d::Zero());  // invalid frames do not count
  const BoneLengths lengths = subject_bone_lengths(frames);
  const BoneLengths truth = bone_lengths(frames[0].joints);
  for (size_t b = 0; b < lengths.size(); ++b) CHECK(lengths[b] == Approx(truth[b]).epsilon(1e-9));
  const BvhSkeleton s(lengths);
  const auto& lsho = s.nodes()[static_cast<size_t>(s.find("LSho"))];
  CHECK(lsho.offset.x() > 0);  // the left arm rests along +X, in centimetres
  CHECK(lsho.offset.norm() == Approx(truth[3] / 10).epsilon(1e-9));
  CHECK(s.find("Chest_LSho") >= 0);
  std::ostringstream out;
  s.write_header(out, 3, 1.0 / 30);
  CHECK(out.str().rfind("HIERARCHY\nROOT LBack\n", 0) == 0);
  CHECK(out.str().find("MOTION\nFrames: 3\nFrame Time: 0.03333333\n") != std::string::npos);
  std::vector<SkeletonFrame> none(2);
  CHECK_THROWS_AS(subject_bone_lengths(none), Error);
  BoneLengths bad = lengths;
  bad[4] = std::nan("");
  CHECK_THROWS_WITH(BvhSkeleton(bad), Catch::Contains("bone 4"));
}

TEST_CASE(
    "humanoid map: the T-pose is the rest (identity rotations); a bent elbow turns only the "
    "forearm") {
  const auto m = synth::make_builtin_motion("tpose", {});
  JointPositions j;
  m->sample(0, j);
  const BvhSkeleton s(bone_lengths(j));
  const HumanoidMap map(s);
  std::array<HumanoidBone, kNumHumanoidBones> bones;
  map.pose(j, bones);
  const auto angle = [](const Eigen::Quaterniond& q) {
    return Eigen::AngleAxisd(q).angle() * 180 / 3.14159265358979;
  };
  std::map<std::string, double> before;
  for (const auto& b : bones) before[std::string(b.name)] = angle(b.rotation);
  JointPositions bent = j;
  const Eigen::Vector3d elbow = j[index(Joint::LElb)];
  const Eigen::AngleAxisd turn(3.14159265358979 / 2, Eigen::Vector3d::UnitZ());
  for (Joint k : {Joint::LHand, Joint::LFTip})
    bent[static_cast<size_t>(index(k))] = elbow + turn * (j[static_cast<size_t>(index(k))] - elbow);
  map.pose(bent, bones);
  for (const auto& b : bones) {
    INFO(b.name);
    const double change = std::abs(angle(b.rotation) - before[std::string(b.name)]);
    if (b.name == "LeftLowerArm")
      CHECK(change == Approx(90).margin(1));
    else
      CHECK(change < 1e-6);
  }
}

TEST_CASE("gaps: short runs between fresh poses are interpolated, long ones and ends flagged") {
  std::vector<SkeletonFrame> frames(20);
  for (size_t f = 0; f < frames.size(); ++f) {
    frames[f].valid = true;
    frames[f].joints.fill(Eigen::Vector3d(static_cast<double>(f) * 10, 0, 1000));
  }
  for (int f : {0, 5, 6, 10, 11, 12, 13, 19}) {
    frames[static_cast<size_t>(f)].valid = false;
    frames[static_cast<size_t>(f)].joints.fill(Eigen::Vector3d::Zero());
  }
  const GapReport r = fill_gaps(frames, 3);
  CHECK(r.filled == 2);   // 5, 6
  CHECK(r.missing == 6);  // 0; 10-13 (longer than 3); 19
  CHECK(r.state[5] == FrameState::Filled);
  CHECK(frames[5].joints[0].x() == Approx(50));
  CHECK(frames[6].joints[0].x() == Approx(60));
  CHECK(r.state[11] == FrameState::Missing);
  REQUIRE(r.missing_ranges.size() == 3);
  CHECK(r.missing_ranges[1] == std::make_pair(10, 13));
  CHECK(r.state[4] == FrameState::Measured);
}

TEST_CASE("takes: an estimate CSV with a skipped frame; bad files are errors naming the file") {
  const fs::path d = temp_dir("csv");
  {
    std::ofstream out(d / "est.csv");
    out << "frame,valid,reason";
    for (auto n : kJointNames) out << ',' << n << "_x," << n << "_y," << n << "_z";
    out << "\n";
    for (int f : {3, 4, 6}) {
      out << f << ",1,0";
      for (int k = 0; k < 75; ++k) out << "," << f * 100 + k;
      out << "\n";
    }
  }
  const Take t = read_take(d / "est.csv", 25);
  REQUIRE(t.frames.size() == 4);
  CHECK(t.fps == 25);
  CHECK(t.inserted == 1);
  CHECK_FALSE(t.frames[2].valid);
  CHECK(t.frames[2].seq == 5);
  CHECK(t.frames[3].joints[1].y() == Approx(604));
  std::ofstream(d / "bad.csv") << "frame,valid,reason,HeadTop_x\n1,1,0,abc\n";
  CHECK_THROWS_WITH(read_take(d / "bad.csv"), Catch::Contains("bad.csv"));
  CHECK_THROWS_WITH(read_take(d / "missing.csv"), Catch::Contains("missing.csv"));
  CHECK_THROWS_WITH(read_take(d / "est.csv", -1), Catch::Contains("frame rate"));
}

TEST_CASE(
    "takes: an lcm-logger log; malformed events counted, missing sequences inserted, rate from "
    "utime") {
  const fs::path d = temp_dir("log");
  {
    lcm::LogFile log((d / "take.lcmlog").string(), "w");
    REQUIRE(log.good());
    const auto m = synth::make_builtin_motion("walk", {});
    hullpose_msg::skeleton_t msg;
    int64_t eventnum = 0;
    const auto write = [&](const std::string& channel, const std::vector<uint8_t>& bytes) {
      lcm::LogEvent e;
      e.eventnum = eventnum++;
      e.timestamp = 1000 * eventnum;
      e.channel = channel;
      e.datalen = static_cast<int32_t>(bytes.size());
      e.data = const_cast<uint8_t*>(bytes.data());
      REQUIRE(log.writeEvent(&e) == 0);
    };
    for (int k = 0; k < 10; ++k) {
      if (k == 4) continue;  // never received
      SkeletonFrame f;
      m->sample(k / 50.0, f.joints);
      f.seq = 100 + k;
      f.utime = 1'700'000'000'000'000 + k * 20'000;  // 50 Hz
      f.valid = true;
      to_message(f, "rigA", msg);
      std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
      msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
      write("SKELETON", bytes);
      if (k == 6) {
        bytes.resize(bytes.size() / 2);  // truncated in transit
        write("SKELETON", bytes);
      }
      write("OTHER", {1, 2, 3});
    }
  }
  const Take t = read_take(d / "take.lcmlog");
  REQUIRE(t.frames.size() == 10);
  CHECK(t.fps == Approx(50));
  CHECK(t.malformed == 1);
  CHECK(t.inserted == 1);
  CHECK(t.frames[0].seq == 100);
  CHECK_FALSE(t.frames[4].valid);
  CHECK(t.frames[5].valid);
  CHECK_THROWS_WITH(read_take(d / "take.lcmlog", 30, "NOPE"),
                    Catch::Contains("no skeleton_t message on channel 'NOPE'"));
}

TEST_CASE("drop-oldest queue: bounded, keeps the newest, counts what it dropped") {
  DropOldestQueue<int> q(3);
  for (int i = 0; i < 10; ++i) q.push(i);
  CHECK(q.size() == 3);
  CHECK(q.dropped() == 7);
  CHECK(q.pushed() == 10);
  CHECK(q.front() == 7);
  q.pop();
  CHECK(q.front() == 8);
  CHECK(DropOldestQueue<int>(0).capacity() == 1);
}

TEST_CASE("subscription: skeletons and statuses from the bus; malformed and foreign ones counted") {
  const auto bus = bus::open_bus("memq://");
  int skeletons = 0, statuses = 0;
  SubscriptionOptions o;
  o.rig_id = "rigA";
  Subscription sub(
      *bus, o, [&](const SkeletonFrame& f, int64_t) { skeletons += f.seq == 7 ? 1 : 100; },
      [&](const hullpose_msg::node_status_t& s) { statuses += s.role == "camera_node" ? 1 : 100; });
  SkeletonFrame f;
  f.seq = 7;
  f.valid = true;
  hullpose_msg::skeleton_t msg;
  to_message(f, "rigA", msg);
  wire::publish(*bus, "SKELETON", msg);
  to_message(f, "rigB", msg);
  wire::publish(*bus, "SKELETON", msg);
  const std::vector<uint8_t> garbage = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  bus->publish("SKELETON", garbage);
  bus->publish("STATUS", garbage);
  hullpose_msg::node_status_t s{};
  s.rig_id = "rigA";
  s.role = "camera_node";
  wire::publish(*bus, "STATUS", s);
  sub.poll(0);
  CHECK(skeletons == 1);
  CHECK(statuses == 1);
  CHECK(sub.counters().get("malformed_skeleton") == 1);
  CHECK(sub.counters().get("malformed_status") == 1);
  CHECK(sub.counters().get("foreign_rig") == 1);
}

TEST_CASE("subscription: hulls checked field by field; hostile ones counted, never drawn") {
  const auto bus = bus::open_bus("memq://");
  std::vector<int64_t> drawn;
  SubscriptionOptions o;
  o.rig_id = "rigA";
  Subscription sub(
      *bus, o, [](const SkeletonFrame&, int64_t) {}, {},
      [&](const msg::CoarseHull& h) { drawn.push_back(h.trigger_seq); });
  msg::CoarseHull h;
  h.dims = {4, 3, 2};
  h.origin_mm = {-100, -100, 0};
  h.voxel_mm = 100;
  h.carved_voxel_mm = 25;
  h.occupancy = cv::Mat::zeros(6, 4, CV_8UC1);
  h.occupancy.at<uint8_t>(1 + 3 * 1, 2) = 255;  // voxel (2, 1, 1)
  h.num_occupied = 1;
  h.trigger_seq = 5;
  SilhouetteEncoder enc;
  hullpose_msg::hull_t m;
  msg::to_message(h, "rigA", enc, m);
  wire::publish(*bus, "HULL", m);
  auto bad = m;
  bad.nx = 65;
  wire::publish(*bus, "HULL", bad);
  bad = m;
  bad.num_occupied = 2;
  wire::publish(*bus, "HULL", bad);
  bad = m;
  bad.rig_id = "rigB";
  wire::publish(*bus, "HULL", bad);
  const std::vector<uint8_t> garbage = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  bus->publish("HULL", garbage);
  sub.poll(0);
  CHECK(drawn == std::vector<int64_t>{5});
  CHECK(sub.counters().get("invalid_hull_bad_dims") == 1);
  CHECK(sub.counters().get("invalid_hull_bad_count") == 1);
  CHECK(sub.counters().get("foreign_rig") == 1);
  CHECK(sub.counters().get("malformed_hull") == 1);
}

TEST_CASE("BVH: with a held body model, the hierarchy has the newest model's lengths exactly") {
  const auto m = synth::make_builtin_motion("walk", {});
  // 9 provisional frames whose bones are 3 % long, then 3 of held model 1 and 2 of model 2
  // (5 % short): the median of all would be provisional; the hierarchy must be model 2's.
  std::vector<SkeletonFrame> frames(14);
  for (size_t f = 0; f < frames.size(); ++f) {
    m->sample(static_cast<double>(f) / 30.0, frames[f].joints);
    frames[f].valid = true;
    frames[f].model_version = f < 9 ? 0 : f < 12 ? 1 : 2;
    const double scale = f < 9 ? 1.03 : f < 12 ? 1.0 : 0.95;
    const Eigen::Vector3d root = frames[f].joints[static_cast<size_t>(index(Joint::Chest))];
    for (auto& j : frames[f].joints) j = root + scale * (j - root);
  }
  frames[13].valid = false;  // an invalid frame of model 2 does not count
  CHECK(held_model_version(frames) == 2);
  const BoneLengths lengths = subject_bone_lengths(frames);
  const BoneLengths truth = bone_lengths(frames[12].joints);
  for (size_t b = 0; b < lengths.size(); ++b) CHECK(lengths[b] == Approx(truth[b]).epsilon(1e-12));
  for (auto& f : frames) f.model_version = 0;
  CHECK(held_model_version(frames) == 0);
  CHECK(subject_bone_lengths(frames)[5] == Approx(bone_lengths(frames[4].joints)[5]).epsilon(0.02));
  // model_version travels over the wire; a negative one is refused.
  hullpose_msg::skeleton_t msg;
  frames[12].model_version = 2;
  to_message(frames[12], "rigA", msg);
  SkeletonFrame back;
  REQUIRE(from_message(msg, back));
  CHECK(back.model_version == 2);
  msg.model_version = -1;
  CHECK_FALSE(from_message(msg, back));
}
