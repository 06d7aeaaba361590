#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <sstream>

#include "fixtures.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/eval/cli.hpp"
#include "hullpose/eval/consistency.hpp"
#include "hullpose/eval/metrics.hpp"
#include "hullpose/eval/report.hpp"

using namespace hullpose;
using namespace hullpose::eval;
using namespace hullpose::eval::test;
namespace fs = std::filesystem;

namespace {

constexpr double kStature = 1834;  // the thesis' dance-whirl subject
constexpr int kFrames = 60;

std::vector<PoseRecord> as_estimates(std::vector<PoseRecord> truth) {
  for (auto& r : truth) {
    r.utime = 0;
    r.valid = true;
    r.reason = 0;
  }
  return truth;
}

std::vector<PoseRecord> offset(std::vector<PoseRecord> records, const Eigen::Vector3d& d) {
  for (auto& r : records)
    for (auto& p : r.joints) p += d;
  return records;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Cli {
  int status = -1;
  std::string out, err;
};
Cli run(const std::vector<std::string>& args) {
  std::vector<const char*> argv{"hullpose-eval"};
  for (const auto& a : args) argv.push_back(a.c_str());
  std::ostringstream out, err;
  Cli c;
  c.status = hullpose::run_tool(
      "hullpose-eval", static_cast<int>(argv.size()), argv.data(),
      [&out](int argc, const char* const* v) { return run_cli(argc, v, out); }, err);
  c.out = out.str();
  c.err = err.str();
  return c;
}

}  // namespace

TEST_CASE("box statistics follow the 1.5 IQR convention (hand-computed)") {
  // Sorted: 1..9, 100. Quantiles by linear interpolation at (n-1)p: q1 at 2.25 -> 3.25,
  // median at 4.5 -> 5.5, q3 at 6.75 -> 7.75; IQR 4.5, fences -3.5 and 14.5.
  const BoxStats b = box_stats({7, 100, 3, 1, 9, 2, 8, 4, 6, 5});
  CHECK(b.count == 10);
  CHECK(b.mean == Approx(14.5));
  CHECK(b.std == Approx(std::sqrt(10285.0 / 10 - 14.5 * 14.5)));  // population std, 28.605
  CHECK(b.min == 1);
  CHECK(b.max == 100);
  CHECK(b.q1 == Approx(3.25));
  CHECK(b.median == Approx(5.5));
  CHECK(b.q3 == Approx(7.75));
  CHECK(b.whisker_low == 1);
  CHECK(b.whisker_high == 9);
  CHECK(b.outliers == std::vector<double>{100});

  // A low outlier: -50, 10..14. q1 at 1.25 -> 10.25, median 11.5, q3 at 3.75 -> 12.75,
  // fences 6.5 and 16.5.
  const BoxStats c = box_stats({14, 13, -50, 12, 11, 10});
  CHECK(c.q1 == Approx(10.25));
  CHECK(c.median == Approx(11.5));
  CHECK(c.q3 == Approx(12.75));
  CHECK(c.whisker_low == 10);
  CHECK(c.whisker_high == 14);
  CHECK(c.outliers == std::vector<double>{-50});

  const BoxStats one = box_stats({42});
  CHECK(one.q1 == 42);
  CHECK(one.q3 == 42);
  CHECK(one.whisker_low == 42);
  CHECK(one.std == 0);
  CHECK(one.outliers.empty());

  const BoxStats none = box_stats({});
  CHECK(none.count == 0);
  CHECK(std::isnan(none.mean));
  CHECK(std::isnan(none.median));
}

TEST_CASE("stature from joints recovers the stature of a ratio-built skeleton in any pose") {
  for (int f : {0, 7, 22})
    CHECK(stature_from_joints(walking_pose(f, kStature)) == Approx(kStature));
  CHECK(stature_from_joints(walking_pose(3, 1200)) == Approx(1200));
}

TEST_CASE("ground truth against itself scores 0 mm and 100 %") {
  TempDir dir("self");
  const auto truth = walking_truth(kFrames, kStature);
  write_dataset(dir.path / "ds", truth, kStature);
  write_estimates(dir.path / "est.csv", as_estimates(truth));
  const EvalResult r = evaluate_files(dir.path / "ds", dir.path / "est.csv");
  CHECK(r.frames == kFrames);
  CHECK(r.scored_frames == kFrames);
  CHECK(r.invalid_frames == 0);
  CHECK(r.missing_frames == 0);
  CHECK(r.valid_pct == 100);
  CHECK(r.all_joints.mean == 0);
  CHECK(r.all_joints.max == 0);
  CHECK(r.extremities.mean == 0);
  CHECK(r.hands_feet.mean == 0);
  CHECK(r.pck50_pct == 100);
  CHECK(r.pck100_pct == 100);
  CHECK(r.lr_correct_pct == 100);
  CHECK(r.stature_error_mm == Approx(0).margin(1e-9));
  CHECK(r.stature_meta_mm == kStature);
  CHECK(r.stature_est_mm == Approx(kStature).epsilon(1e-6));  // the CSV rounds to 0.001 mm
  for (const BoxStats& b : r.per_joint) CHECK(b.max == 0);
  REQUIRE(r.per_frame.size() == kFrames);
  CHECK(r.per_frame[17].status == FrameStatus::Scored);
  CHECK(r.per_frame[17].mean_mm == 0);
}

TEST_CASE("a constant offset is reported as exactly that offset") {
  const auto truth = walking_truth(kFrames, kStature);
  const Eigen::Vector3d d(36, 0, -48);  // 60 mm
  SECTION("in memory") {
    const EvalResult r =
        evaluate(truth, offset(as_estimates(truth), d), walking_meta(kFrames, kStature));
    CHECK(r.all_joints.mean == Approx(60).margin(1e-9));
    CHECK(r.all_joints.median == Approx(60).margin(1e-9));
    CHECK(r.all_joints.std == Approx(0).margin(1e-9));
    CHECK(r.extremities.mean == Approx(60).margin(1e-9));
    CHECK(r.hands_feet.mean == Approx(60).margin(1e-9));
    for (const BoxStats& b : r.per_joint) {
      CHECK(b.mean == Approx(60).margin(1e-9));
      CHECK(b.q1 == Approx(60).margin(1e-9));
      CHECK(b.q3 == Approx(60).margin(1e-9));
    }
    CHECK(r.axis_bias_mm.x() == Approx(36).margin(1e-9));
    CHECK(r.axis_bias_mm.y() == Approx(0).margin(1e-9));
    CHECK(r.axis_bias_mm.z() == Approx(-48).margin(1e-9));
    CHECK(r.axis_abs_mm.z() == Approx(48).margin(1e-9));
    CHECK(r.pck50_pct == 0);
    CHECK(r.pck100_pct == 100);
    CHECK(r.lr_correct_pct == 100);                       // a shift never swaps sides
    CHECK(r.stature_error_mm == Approx(0).margin(1e-9));  // nor changes bone lengths
  }
  SECTION("through the files and --json") {
    TempDir dir("offset");
    write_dataset(dir.path / "ds", truth, kStature);
    write_estimates(dir.path / "est.csv", offset(as_estimates(truth), Eigen::Vector3d(12, 0, -9)));
    const Cli c = run(
        {"--gt", (dir.path / "ds").string(), "--est", (dir.path / "est.csv").string(), "--json"});
    INFO(c.err);
    REQUIRE(c.status == 0);
    const auto j = nlohmann::json::parse(c.out);
    CHECK(j["mpjpe_mm"] == 15.0);  // three decimals, as the table
    CHECK(j["mpjpe_std_mm"] == 0.0);
    CHECK(j["extremity_mpjpe_mm"] == 15.0);
    CHECK(j["hands_feet_mpjpe_mm"] == 15.0);
    CHECK(j["pck50_pct"] == 100.0);
    CHECK(j["axis_bias_mm"] == nlohmann::json({{"x", 12.0}, {"y", 0.0}, {"z", -9.0}}));
    const EvalResult r = evaluate_files(dir.path / "ds", dir.path / "est.csv");
    CHECK(r.all_joints.mean == Approx(15).margin(1e-6));  // the CSV holds 0.001 mm
    CHECK(r.all_joints.max == Approx(15).margin(1e-6));
  }
}

TEST_CASE("bone lengths are scored against the truth's, bone by bone") {
  const auto truth = walking_truth(kFrames, kStature);
  SECTION("a moved skeleton has every bone right") {
    const EvalResult r = evaluate(truth, offset(as_estimates(truth), Eigen::Vector3d(40, 0, 30)),
                                  walking_meta(kFrames, kStature));
    for (double e : r.bone_length_error_pct) CHECK(e == Approx(0).margin(1e-3));
    CHECK(r.bone_length_error_median_abs_pct == Approx(0).margin(1e-3));
  }
  SECTION("a forearm 20 % long and a spine 10 % short are named, the rest is right") {
    auto est = as_estimates(truth);
    const int forearm = 7, spine = 12;  // kBones: LElb-LHand, UBack-Back
    REQUIRE(kBones[forearm].child == Joint::LHand);
    REQUIRE(kBones[spine].child == Joint::Back);
    for (PoseRecord& p : est) {
      // Rebuilt from the chest outwards (kBones lists parents first): everything beyond a
      // stretched bone moves with it, so no other bone changes.
      const JointPositions given = p.joints;
      for (int b = 0; b < kNumBones; ++b) {
        const int parent = index(kBones[b].parent), child = index(kBones[b].child);
        const double factor = b == forearm ? 1.2 : b == spine ? 0.9 : 1.0;
        p.joints[child] = p.joints[parent] + factor * (given[child] - given[parent]);
      }
    }
    const EvalResult r = evaluate(truth, est, walking_meta(kFrames, kStature));
    for (int b = 0; b < kNumBones; ++b) {
      const double want = b == forearm ? 20 : b == spine ? -10 : 0;
      INFO(bone_key(b));
      CHECK(r.bone_length_error_pct[static_cast<size_t>(b)] == Approx(want).margin(1e-3));
    }
    CHECK(r.bone_length_error_median_abs_pct == Approx(0).margin(1e-3));
  }
}

TEST_CASE("per-frame statistics summarise the Fig. 6.1 curve") {
  // Frame f is shifted by 10 f mm along x: per-frame means 0, 10, 20, 30, 40.
  const auto truth = walking_truth(5, kStature);
  auto est = as_estimates(truth);
  for (auto& rec : est)
    for (auto& p : rec.joints) p.x() += 10.0 * rec.frame;
  est[1].valid = false;  // leaves 0, 20, 30, 40
  const EvalResult r = evaluate(truth, est, walking_meta(5, kStature));
  CHECK(r.frame_mean.count == 4);
  CHECK(r.frame_mean.mean == Approx(22.5));
  CHECK(r.frame_mean.median == Approx(25));
  CHECK(r.frame_mean.std ==
        Approx(std::sqrt((22.5 * 22.5 + 2.5 * 2.5 + 7.5 * 7.5 + 17.5 * 17.5) / 4)));
  CHECK(r.frame_mean.max == Approx(40));
  CHECK(r.worst_frame == 4);
  CHECK(r.frame_hands_feet.median == Approx(25));
  CHECK(r.all_joints.mean == Approx(r.frame_mean.mean));
  CHECK(r.per_frame[3].mean_mm == Approx(30));
  CHECK(r.per_frame[3].hands_feet_mm == Approx(30));
  CHECK(r.per_frame[3].axis_bias_mm.x() == Approx(30));
}

TEST_CASE("left/right swaps are detected per limb") {
  const auto truth = walking_truth(kFrames, kStature);
  auto est = as_estimates(truth);
  for (int f = 10; f < 20; ++f)
    est[static_cast<size_t>(f)].joints =
        mirrored(truth[static_cast<size_t>(f)].joints, true, false);
  for (int f = 30; f < 35; ++f)
    est[static_cast<size_t>(f)].joints =
        mirrored(truth[static_cast<size_t>(f)].joints, false, true);
  for (int f = 40; f < 42; ++f)
    est[static_cast<size_t>(f)].joints = mirrored(truth[static_cast<size_t>(f)].joints, true, true);
  const EvalResult r = evaluate(truth, est, walking_meta(kFrames, kStature));
  CHECK(r.lr_arms_correct_pct == Approx(100.0 * (kFrames - 12) / kFrames));
  CHECK(r.lr_legs_correct_pct == Approx(100.0 * (kFrames - 7) / kFrames));
  CHECK(r.lr_correct_pct == Approx(100.0 * (kFrames - 17) / kFrames));
  CHECK_FALSE(r.per_frame[12].lr_arms_correct);
  CHECK(r.per_frame[12].lr_legs_correct);
  CHECK(r.per_frame[31].lr_arms_correct);
  CHECK_FALSE(r.per_frame[31].lr_legs_correct);
  CHECK_FALSE(r.per_frame[41].lr_arms_correct);
  CHECK_FALSE(r.per_frame[41].lr_legs_correct);
  CHECK(r.per_frame[25].lr_arms_correct);
  CHECK(r.per_frame[25].lr_legs_correct);
  // The swap also shows as error on the limbs, and only there.
  CHECK(r.per_joint[index(Joint::LHand)].max > 100);
  CHECK(r.per_joint[index(Joint::Chest)].max == 0);

  // Noise far smaller than the shoulder width does not flip the verdict.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 25);
  auto noisy = as_estimates(truth);
  for (auto& rec : noisy)
    for (auto& p : rec.joints) {
      // z first: the order x86-64 GCC evaluated one call's arguments in (unspecified in C++).
      const double z = noise(rng), y = noise(rng), x = noise(rng);
      p += Eigen::Vector3d(x, y, z);
    }
  CHECK(evaluate(truth, noisy, walking_meta(kFrames, kStature)).lr_correct_pct == 100);
}

TEST_CASE("invalid and missing frames are counted, not scored and not dropped") {
  TempDir dir("gaps");
  const auto truth = walking_truth(kFrames, kStature);
  write_dataset(dir.path / "ds", truth, kStature);
  std::vector<PoseRecord> est;
  for (auto rec : as_estimates(truth)) {
    if (rec.frame >= 5 && rec.frame <= 7) continue;  // missing
    if (rec.frame == 0) continue;                    // missing at the start
    if (rec.frame == 10 || rec.frame == 11 || rec.frame == 40) {
      rec.valid = false;  // invalid: garbage joints must not count
      rec.reason = rec.frame == 40 ? 1 : 4;
      for (auto& p : rec.joints) p.setZero();
    }
    est.push_back(rec);
  }
  est.pop_back();  // missing at the end
  write_estimates(dir.path / "est.csv", est);
  const EvalResult r = evaluate_files(dir.path / "ds", dir.path / "est.csv");
  CHECK(r.frames == kFrames);
  CHECK(r.missing_frames == 5);
  CHECK(r.invalid_frames == 3);
  CHECK(r.scored_frames == kFrames - 8);
  CHECK(r.invalid_reasons == std::map<int, int>{{1, 1}, {4, 2}});
  CHECK(r.valid_pct == Approx(100.0 * (kFrames - 8) / kFrames));
  CHECK(r.all_joints.mean == 0);  // the zeroed invalid frames did not leak in
  CHECK(r.all_joints.count == static_cast<size_t>((kFrames - 8) * kNumJoints));
  CHECK(r.pck100_valid_pct == 100);
  CHECK(r.pck100_pct == Approx(100.0 * (kFrames - 8) / kFrames));  // failures are misses
  CHECK(r.lr_correct_pct == 100);
  REQUIRE(r.per_frame.size() == kFrames);
  CHECK(r.per_frame[0].status == FrameStatus::Missing);
  CHECK(r.per_frame[6].status == FrameStatus::Missing);
  CHECK(r.per_frame[kFrames - 1].status == FrameStatus::Missing);
  CHECK(r.per_frame[10].status == FrameStatus::Invalid);
  CHECK(r.per_frame[10].reason == 4);
  CHECK(std::isnan(r.per_frame[10].mean_mm));
  CHECK(r.per_frame[12].status == FrameStatus::Scored);

  const Cli c =
      run({"--gt", (dir.path / "ds").string(), "--est", (dir.path / "est.csv").string(), "--json"});
  REQUIRE(c.status == 0);
  CHECK(c.out.find("\"missing_frames\":5,") != std::string::npos);
  CHECK(c.out.find("\"invalid_reasons\":{\"too_few_cameras\":1,\"pose_jump\":2}") !=
        std::string::npos);

  const Cli table = run({"--gt", (dir.path / "ds").string(), "--est",
                         (dir.path / "est.csv").string(), "--report", (dir.path / "rep").string()});
  REQUIRE(table.status == 0);
  const std::string csv = slurp(dir.path / "rep" / "per_frame.csv");
  CHECK(csv.find("\n0,missing,,,,,,,,,,,,,,,1\n") != std::string::npos);
  CHECK(csv.find("\n10,invalid,pose_jump,,,,,,,,,,,,,,1\n") != std::string::npos);
  CHECK(csv.find("\n12,scored,ok,0.000,") != std::string::npos);
  CHECK(std::regex_search(table.out, std::regex(R"(missing from the estimate file +5\n)")));
  CHECK(table.out.find("pose_jump=2") != std::string::npos);
}

TEST_CASE("an estimate with no valid frame still reports, with nulls") {
  const auto truth = walking_truth(10, kStature);
  auto est = as_estimates(truth);
  for (auto& rec : est) rec.valid = false;
  const EvalResult r = evaluate(truth, est, walking_meta(10, kStature));
  CHECK(r.valid_pct == 0);
  CHECK(r.pck100_pct == 0);
  CHECK(std::isnan(r.all_joints.mean));
  CHECK(std::isnan(r.lr_correct_pct));
  CHECK(std::isnan(r.bone_length_error_median_abs_pct));
  std::ostringstream json;
  write_json(json, r);
  const auto j = nlohmann::json::parse(json.str());
  CHECK(j["mpjpe_mm"].is_null());
  CHECK(j["bone_length_error_median_abs_pct"].is_null());
  CHECK(j["valid_pct"] == 0.0);
  std::ostringstream table;
  write_table(table, r, {"ds", "est.csv", "walk"});
  CHECK(std::regex_search(table.str(), std::regex(R"(all joints \(MPJPE\) +- mm)")));

  // The page still renders, with empty plots, for no scored frame and for a single frame.
  TempDir dir("empty");
  const std::string html =
      slurp(write_html_report(dir.path / "none", r, {"ds", "est.csv", "walk"}));
  CHECK(html.find("<svg class='plot' id='plot-joints'") != std::string::npos);
  CHECK(html.find("nan") == std::string::npos);
  const std::vector<PoseRecord> one(truth.begin(), truth.begin() + 1);
  const EvalResult single = evaluate(one, as_estimates(one), walking_meta(1, kStature));
  CHECK(single.all_joints.mean == 0);
  const std::string html1 =
      slurp(write_html_report(dir.path / "one", single, {"ds", "est.csv", "walk"}));
  CHECK(html1.find("nan") == std::string::npos);
  CHECK(html1.find("inf") == std::string::npos);
}

TEST_CASE("--json carries the agreed keys and --report writes the page") {
  TempDir dir("cli");
  const auto truth = walking_truth(kFrames, kStature);
  write_dataset(dir.path / "ds", truth, kStature);
  write_estimates(dir.path / "est.csv", offset(as_estimates(truth), Eigen::Vector3d(0, 20, 0)));
  const Cli c = run({"--gt", (dir.path / "ds").string(), "--est", (dir.path / "est.csv").string(),
                     "--json", "--report", (dir.path / "rep").string()});
  INFO(c.err);
  REQUIRE(c.status == 0);
  CHECK(c.out.front() == '{');
  CHECK(c.out.back() == '\n');
  CHECK(std::count(c.out.begin(), c.out.end(), '\n') == 1);
  for (const char* key :
       {"frames", "valid_pct", "mpjpe_mm", "extremity_mpjpe_mm", "pck100_pct", "lr_correct_pct",
        "stature_error_mm", "pck50_pct", "hands_feet_mpjpe_mm", "mpjpe_median_mm", "mpjpe_std_mm",
        "per_joint", "RToe", "bone_length_error_pct", "LElb-LHand",
        "bone_length_error_median_abs_pct"})
    CHECK(c.out.find("\"" + std::string(key) + "\":") != std::string::npos);
  const std::string html = slurp(dir.path / "rep" / "report.html");
  REQUIRE(!html.empty());
  size_t plots = 0;
  for (size_t at = html.find("<svg class='plot'"); at != std::string::npos;
       at = html.find("<svg class='plot'", at + 1))
    ++plots;
  CHECK(plots == 5);
  // Self-contained: nothing for the browser to fetch.
  for (const char* fetch :
       {"src=", "href=", "<link", "url(", "@import", "fetch(", "XMLHttpRequest"})
    CHECK(html.find(fetch) == std::string::npos);
  CHECK(html.find("walk (test)") != std::string::npos);

  const std::string csv = slurp(dir.path / "rep" / "per_frame.csv");
  CHECK(std::count(csv.begin(), csv.end(), '\n') == kFrames + 1);
  CHECK(csv.rfind("frame,status,reason,mean_mm,", 0) == 0);
  CHECK(csv.find("\n7,scored,ok,20.000,20.000,20.000,0.000,20.000,0.000,0.000,20.000,0.000,1,1,") !=
        std::string::npos);
}

TEST_CASE("bad input gets a clear error naming the file") {
  TempDir dir("bad");
  const auto truth = walking_truth(20, kStature);
  const fs::path ds = dir.path / "ds", est = dir.path / "est.csv";
  write_dataset(ds, truth, kStature);
  write_estimates(est, as_estimates(truth));
  auto expect = [&](std::vector<std::string> args, const std::string& needle) {
    const Cli c = run(args);
    INFO(c.err);
    CHECK(c.status == 2);
    CHECK(c.err.rfind("hullpose-eval: error: ", 0) == 0);
    CHECK(c.err.find(needle) != std::string::npos);
  };
  expect({"--est", est.string()}, "--gt DIR is required");
  const Cli help = run({"--help"});
  CHECK(help.status == 0);
  CHECK(help.out.find("usage: hullpose-eval --gt DIR --est FILE") != std::string::npos);
  expect({"--gt", ds.string(), "--est"}, "--est needs a value");
  expect({"--gt", ds.string(), "--est", est.string(), "--frobnicate"},
         "unknown option '--frobnicate'");
  expect({"--gt", (dir.path / "nope").string(), "--est", est.string()},
         "nope: not a dataset directory");
  expect({"--gt", ds.string(), "--est", (dir.path / "none.csv").string()}, "none.csv: cannot open");

  // Frames the ground truth does not have.
  auto extra = as_estimates(walking_truth(25, kStature));
  write_estimates(dir.path / "long.csv", extra);
  expect({"--gt", ds.string(), "--est", (dir.path / "long.csv").string()},
         "long.csv: frame 20 is not a ground-truth frame (the ground truth has 20 frames, 0..19)");
  auto shifted = as_estimates(truth);
  shifted.front().frame = -3;
  write_estimates(dir.path / "neg.csv", shifted);
  expect({"--gt", ds.string(), "--est", (dir.path / "neg.csv").string()},
         "neg.csv: frame -3 is not a ground-truth frame");
  write_estimates(dir.path / "empty.csv", {});
  expect({"--gt", ds.string(), "--est", (dir.path / "empty.csv").string()}, "empty.csv: no frames");

  // Malformed CSV: the reader names file and line.
  {
    std::ifstream in(est);
    std::string header, first;
    std::getline(in, header);
    std::getline(in, first);
    std::ofstream(dir.path / "cut.csv") << header << '\n'
                                        << first << '\n'
                                        << first.substr(0, 40) << '\n';
  }
  expect({"--gt", ds.string(), "--est", (dir.path / "cut.csv").string()},
         "cut.csv:3: expected 79 fields");

  // Meta and ground truth disagree.
  auto meta = walking_meta(21, kStature);
  write_meta(DatasetPaths(ds).meta(), meta);
  expect({"--gt", ds.string(), "--est", est.string()}, "ground_truth.csv: has 20 frames but");
  fs::remove(DatasetPaths(ds).meta());
  expect({"--gt", ds.string(), "--est", est.string()}, "meta.json: not found");
}

TEST_CASE("frames whose true body leaves the capture volume are counted apart") {
  const auto truth = walking_truth(kFrames, kStature);
  // The walk goes along -y: a volume that holds its first half only.
  double min_y = 1e9, max_y = -1e9;
  for (const auto& rec : truth)
    for (const auto& p : rec.joints) {
      min_y = std::min(min_y, p.y());
      max_y = std::max(max_y, p.y());
    }
  CaptureVolume v;
  v.min_mm = Eigen::Vector3d(-5000, 0.5 * (min_y + max_y), 0);
  v.max_mm = Eigen::Vector3d(5000, max_y + 500, 5000);
  int inside = 0;
  for (const auto& rec : truth) inside += in_capture_volume(rec.joints, v);
  REQUIRE(inside > 0);
  REQUIRE(inside < kFrames);
  auto est = as_estimates(truth);
  int flagged = 0;
  for (auto& rec : est)
    if (!in_capture_volume(truth[static_cast<size_t>(rec.frame)].joints, v) && rec.frame % 2 == 0) {
      rec.valid = false;
      ++flagged;
    }
  const EvalResult r = evaluate(truth, est, walking_meta(kFrames, kStature), "est", &v);
  CHECK(r.frames == inside);
  CHECK(r.out_of_volume_frames == kFrames - inside);
  CHECK(r.out_of_volume_invalid == flagged);
  CHECK(r.out_of_volume_mpjpe_mm == Approx(0).margin(1e-9));  // scored ones are right here
  CHECK(r.valid_pct == Approx(100));
  CHECK(r.invalid_frames == 0);
  // per_frame.csv marks each frame in or out of the volume (its last column).
  TempDir dir("volume");
  write_per_frame_csv(dir.path / "per_frame.csv", r);
  const std::string csv = slurp(dir.path / "per_frame.csv");
  CHECK(csv.rfind("frame,status,", 0) == 0);
  CHECK(std::regex_search(csv, std::regex(",in_volume\n")));
  size_t out_rows = 0;
  for (size_t at = csv.find(",0\n"); at != std::string::npos; at = csv.find(",0\n", at + 1))
    ++out_rows;
  CHECK(out_rows == static_cast<size_t>(kFrames - inside));
  // Without a volume every frame counts.
  CHECK(evaluate(truth, est, walking_meta(kFrames, kStature)).frames == kFrames);
}
