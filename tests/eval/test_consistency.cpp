// Scoring without ground truth (consistency.hpp) on a rendered dataset: its ground truth as the
// estimate agrees with every silhouette and keeps its bone lengths; a displaced skeleton scores
// worse; hullpose-eval switches to it by itself when ground_truth.csv is absent.
#include <catch2/catch.hpp>
#include <filesystem>
#include <random>
#include <sstream>

#include "fixtures.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/eval/cli.hpp"
#include "hullpose/eval/consistency.hpp"
#include "hullpose/synth/dataset_writer.hpp"

using namespace hullpose;
using namespace hullpose::eval;
namespace fs = std::filesystem;

namespace {

const fs::path& dataset() {
  static test::TempDir dir("consistency");
  static const bool written = [] {
    synth::SynthConfig c;
    c.motion = "walk";
    c.frames = 8;
    c.rig = "ring:cameras=5,ceiling=0,width=400,rows=300";
    c.out = dir.path / "data";
    synth::write_dataset(c);
    return true;
  }();
  (void)written;
  return dir.path;
}

std::vector<PoseRecord> truth() {
  return read_ground_truth(DatasetPaths(dataset() / "data").ground_truth());
}

}  // namespace

TEST_CASE("the ground truth as the estimate: 100 % inside, steady bones") {
  const ConsistencyResult r = evaluate_consistency(dataset() / "data", truth());
  CHECK(r.valid_pct == 100);
  CHECK(r.scored_frames == 8);
  CHECK(r.inside_all_pct == 100);
  CHECK(r.frames_n_minus_1_pct == 100);
  for (const CameraAgreement& c : r.cameras) CHECK(c.inside_pct == 100);
  for (double b : r.bone_inside_all_pct) CHECK(b == 100);
  CHECK(r.bone_cv_mean < 1e-4);  // only the file's 0.001 mm rounding
  CHECK(r.jitter_mean_mm < 15);  // a smooth walk
}

TEST_CASE("a displaced or stretched skeleton scores worse") {
  const ConsistencyResult good = evaluate_consistency(dataset() / "data", truth());
  std::vector<PoseRecord> moved = truth(), noisy = truth();
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0, 40);
  for (PoseRecord& p : moved)
    for (auto& j : p.joints) j += Eigen::Vector3d(150, 0, 0);
  for (PoseRecord& p : noisy)
    for (auto& j : p.joints) {
      const double x = n(rng), y = n(rng);  // drawn in sequence: argument order is unspecified
      j += Eigen::Vector3d(x, y, n(rng));
    }
  const ConsistencyResult m = evaluate_consistency(dataset() / "data", moved);
  const ConsistencyResult z = evaluate_consistency(dataset() / "data", noisy);
  CHECK(m.inside_all_pct < good.inside_all_pct - 10);
  CHECK(m.frames_n_minus_1_pct < good.frames_n_minus_1_pct);
  CHECK(z.inside_all_pct < good.inside_all_pct);
  CHECK(z.bone_cv_mean > 0.05);
  CHECK(z.jitter_mean_mm > good.jitter_mean_mm + 30);
  // One hand 250 mm out to the side: its forearm leaves the silhouettes, the other stays inside.
  std::vector<PoseRecord> arm = truth();
  for (PoseRecord& p : arm) {
    const Eigen::Vector3d out = (p.joints[static_cast<size_t>(index(Joint::LSho))] -
                                 p.joints[static_cast<size_t>(index(Joint::Chest))])
                                    .normalized();
    for (Joint j : {Joint::LHand, Joint::LFTip})
      p.joints[static_cast<size_t>(index(j))] += 250 * out;
  }
  const ConsistencyResult a = evaluate_consistency(dataset() / "data", arm);
  auto bone = [](Joint child) {
    REQUIRE(bone_to(child) >= 0);
    return static_cast<size_t>(bone_to(child));
  };
  CHECK(a.bone_inside_all_pct[bone(Joint::LHand)] < 70);
  CHECK(a.bone_inside_all_pct[bone(Joint::RHand)] == 100);
  CHECK(bone_key(static_cast<int>(bone(Joint::LHand))) == "LElb-LHand");
  // Invalid frames are not scored but count against valid %.
  std::vector<PoseRecord> half = truth();
  for (size_t i = 0; i < half.size(); i += 2) half[i].valid = false;
  CHECK(evaluate_consistency(dataset() / "data", half).valid_pct == 50);
}

TEST_CASE("hullpose-eval scores against the silhouettes when the dataset has no ground truth") {
  test::TempDir out("consistency-cli");
  const fs::path data = out.path / "data";
  fs::copy(dataset() / "data", data, fs::copy_options::recursive);
  {
    EstimateWriter w(out.path / "est.csv");
    for (PoseRecord p : truth()) w.write(p);
  }
  fs::remove(DatasetPaths(data).ground_truth());
  const std::string gt = data.string(), est = (out.path / "est.csv").string(),
                    report = (out.path / "report").string();
  const char* argv[] = {"hullpose-eval", "--gt",     gt.c_str(),     "--est",
                        est.c_str(),     "--report", report.c_str(), "--json"};
  std::ostringstream o, e;
  REQUIRE(run_tool(
              "hullpose-eval", 8, argv,
              [&o](int c, const char* const* v) { return run_cli(c, v, o); }, e) == 0);
  CHECK_THAT(o.str(), Catch::Contains("\"mode\":\"consistency\"") &&
                          Catch::Contains("\"inside_all_views_pct\":100.0") &&
                          Catch::Contains("\"LElb-LHand\":100.0") &&
                          Catch::Contains("\"RElb-RHand\":100.0"));
  CHECK(fs::exists(out.path / "report" / "report.html"));
  int pictures = 0;
  for (const auto& entry : fs::directory_iterator(out.path / "report"))
    pictures += entry.path().extension() == ".png";
  CHECK(pictures == 4 * 5);  // 4 frames x 5 cameras
}
