// The offline pipeline's command line, a short end-to-end replay per thinning curve rule, and
// the rows it writes one frame late (--lag-frames).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "hullpose/common/check.hpp"
#include "hullpose/replay/replay.hpp"
#include "hullpose/synth/dataset_writer.hpp"

using namespace hullpose;

namespace {

replay::ReplayOptions parse(std::initializer_list<const char*> args) {
  std::vector<const char*> argv{"hullpose-fusion-host"};
  for (const char* a : args) argv.push_back(a);
  const auto options = replay::parse_replay_args(static_cast<int>(argv.size()), argv.data());
  REQUIRE(options);
  return *options;
}

std::filesystem::path temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("hullpose_test_replay_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// `frames` frames of a built-in motion rendered into dir/data; its path.
std::filesystem::path render(const std::filesystem::path& dir, const char* motion, int frames) {
  synth::SynthConfig config;
  config.motion = motion;
  config.frames = frames;
  config.out = dir / "data";
  synth::write_dataset(config);
  return config.out;
}

std::vector<std::string> read_lines(const std::string& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace

TEST_CASE("--curve-rule selects CK3's curve constraint, ck3 by default") {
  CHECK(parse({"--replay", "d", "--out", "e.csv"}).fusion.curve_rule == thin::CurveRule::kCk3);
  CHECK(parse({"--replay", "d", "--out", "e.csv", "--curve-rule", "isthmus"}).fusion.curve_rule ==
        thin::CurveRule::kIsthmus);
  CHECK(parse({"--replay", "d", "--out", "e.csv", "--curve-rule", "endvoxel"}).fusion.curve_rule ==
        thin::CurveRule::kEndVoxel);
  CHECK(parse({"--curve-rule", "ck3", "--replay", "d", "--out", "e.csv"}).fusion.curve_rule ==
        thin::CurveRule::kCk3);
  CHECK_THROWS_WITH(parse({"--replay", "d", "--out", "e.csv", "--curve-rule", "ultimate"}),
                    Catch::Contains("expected ck3, isthmus or endvoxel"));
  CHECK_THROWS_WITH(parse({"--replay", "d", "--out", "e.csv", "--curve-rule"}),
                    Catch::Contains("needs a value"));
  CHECK_THROWS_WITH(parse({"--replay", "d", "--out", "e.csv", "--frames", "ten"}),
                    Catch::Contains("--frames"));
  CHECK_THROWS_WITH(parse({"--replay", "d", "--out", "e.csv", "--bogus"}),
                    Catch::Contains("unknown option '--bogus'"));
  const char* help[] = {"hullpose-fusion-host", "--replay", "d", "--help"};
  CHECK_FALSE(replay::parse_replay_args(4, help));
  CHECK(parse({"--replay", "d", "--out", "e.csv", "--skeletoniser", "d6i1d"}).fusion.skeletoniser ==
        fusion::Skeletoniser::kD6i1d);
  CHECK_THROWS_WITH(parse({"--replay", "d"}), Catch::Contains("both needed"));
  CHECK(parse({"--replay", "d", "--out", "e.csv"}).lag.frames == 1);
  CHECK(parse({"--replay", "d", "--out", "e.csv", "--lag-frames", "0"}).lag.frames == 0);
  CHECK_THROWS_WITH(parse({"--replay", "d", "--out", "e.csv", "--lag-frames", "2"}),
                    Catch::Contains("--lag-frames"));
}

TEST_CASE("a replay runs with every curve rule and writes one estimate per frame") {
  const auto dir = temp_dir("curve_rule");
  const std::string data = render(dir, "tpose", 2).string();

  std::vector<std::string> estimates;
  for (const char* rule : {"ck3", "isthmus", "endvoxel"}) {
    INFO("rule " << rule);
    const std::string out = (dir / (std::string(rule) + ".csv")).string();
    const replay::ReplayOptions options = parse({"--replay", data.c_str(), "--out", out.c_str(),
                                                 "--resolution", "64", "--curve-rule", rule});
    const replay::ReplaySummary s = replay::run_replay(options);
    CHECK(s.frames == 2);
    if (std::string_view(rule) == "ck3") CHECK(s.valid >= 1);
    const std::vector<std::string> lines = read_lines(out);
    CHECK(lines.size() == 1 + 2);  // header + one row per frame
    std::string all;
    for (const std::string& line : lines) all += line;
    estimates.push_back(all);
  }
  // The rule reaches the thinning: the skeletons, and so the estimates, differ.
  CHECK((estimates[1] != estimates[0] || estimates[2] != estimates[0]));
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "a replay writes the rows the live host publishes: every frame once, in order, smoothed "
    "where it has both neighbours") {
  const auto dir = temp_dir("lag");
  const std::string data = render(dir, "walk", 5).string();
  std::vector<std::vector<std::string>> rows;
  for (const char* lag : {"0", "1"}) {
    const std::string out = (dir / (std::string("lag") + lag + ".csv")).string();
    replay::run_replay(parse({"--replay", data.c_str(), "--out", out.c_str(), "--resolution", "64",
                              "--lag-frames", lag}));
    rows.push_back(read_lines(out));
  }
  REQUIRE(rows[0].size() == 1 + 5);
  REQUIRE(rows[1].size() == 1 + 5);
  const auto head = [](const std::string& row) {
    return row.substr(0, row.find(',', row.find(',') + 1));
  };
  for (size_t i = 0; i < rows[0].size(); ++i)
    CHECK(head(rows[0][i]) == head(rows[1][i]));  // frame, valid
  // The first frame has no frame before it, the last none after it: both as fitted.
  CHECK(rows[1][1] == rows[0][1]);
  CHECK(rows[1][5] == rows[0][5]);
  CHECK(rows[1] != rows[0]);  // the walk's frames between them are smoothed
  std::filesystem::remove_all(dir);
}
