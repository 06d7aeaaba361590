// Renders the HTML report of a perturbed estimate in headless Chromium and checks that every
// plot drew: the page's own marker (body[data-plots-drawn]) from --dump-dom, and each plot's
// ink in a screenshot. The report, the screenshot and the dumped DOM are left in
// <build>/tests/eval/report_artifacts/ for a person to look at.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <regex>
#include <sstream>

#include "fixtures.hpp"
#include "hullpose/eval/report.hpp"

using namespace hullpose;
using namespace hullpose::eval;
using namespace hullpose::eval::test;
namespace fs = std::filesystem;

namespace {

constexpr double kStature = 1834;
constexpr int kFrames = 150;

// A plausible bad estimator: noise, a slow drift, an occasional arm swap, a stretch of invalid
// frames and a few it never delivered.
std::vector<PoseRecord> perturbed(const std::vector<PoseRecord>& truth) {
  std::mt19937 rng(2013);
  std::normal_distribution<double> noise(0, 18);
  std::vector<PoseRecord> out;
  for (const PoseRecord& gt : truth) {
    if (gt.frame >= 95 && gt.frame < 99) continue;  // missing
    PoseRecord r = gt;
    r.utime = 0;
    if (gt.frame >= 60 && gt.frame < 68) {
      r.valid = false;
      r.reason = 4;  // pose jump
    }
    if (gt.frame % 37 == 5) r.joints = mirrored(gt.joints, true, false);
    const Eigen::Vector3d drift(30 * std::sin(gt.frame / 20.0), 15,
                                -10 * std::cos(gt.frame / 30.0));
    for (size_t j = 0; j < kNumJoints; ++j) {
      const double spread = j == index(Joint::LHand) || j == index(Joint::RHand) ? 2.5 : 1.0;
      // z first: the order x86-64 GCC evaluated one call's arguments in (unspecified in C++).
      const double z = noise(rng), y = noise(rng), x = noise(rng);
      r.joints[j] += drift + spread * Eigen::Vector3d(x, y, z);
    }
    out.push_back(r);
  }
  return out;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

cv::Vec3b bgr(const char* hex) {
  const unsigned long v = std::strtoul(hex + 1, nullptr, 16);
  return {static_cast<uchar>(v & 0xff), static_cast<uchar>((v >> 8) & 0xff),
          static_cast<uchar>((v >> 16) & 0xff)};
}

// Pixels within a small tolerance of `hex` (anti-aliased edges differ; line cores do not).
int ink(const cv::Mat& image, const char* hex) {
  const cv::Vec3b c = bgr(hex);
  int n = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      n +=
          std::abs(p[0] - c[0]) <= 12 && std::abs(p[1] - c[1]) <= 12 && std::abs(p[2] - c[2]) <= 12;
    }
  return n;
}

int chromium(const std::string& args, const fs::path& dir, const std::string& tag) {
  const fs::path profile = dir / ("profile-" + tag);
  fs::remove_all(profile);
  const std::string cmd =
      "timeout 120 /usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic "
      "--no-first-run --disable-background-networking --disable-component-update --disable-sync "
      "--user-data-dir='" +
      profile.string() + "' " + args + " 2>'" + (dir / (tag + ".log")).string() + "'";
  const int status = std::system(cmd.c_str());
  fs::remove_all(profile);
  return status;
}

// Appended to a copy of the report: hovers frame 62 (invalid) on the error plot and frame 42
// (arms swapped) on the signed-error plot, recording the tooltip text on <body>.
constexpr const char* kHoverScript = R"JS(<script>
function hoverFrame(id, frame, attr) {
  var svg = document.getElementById(id), d = svg.dataset, p = svg.createSVGPoint();
  p.x = +d.px0 + (frame - d.lo) / (d.hi - d.lo) * (d.px1 - d.px0);
  p.y = +d.top + 20;
  p = p.matrixTransform(svg.getScreenCTM());
  svg.dispatchEvent(new MouseEvent('mousemove', {clientX: p.x, clientY: p.y}));
  document.body.setAttribute(attr, document.getElementById('tip').textContent);
}
hoverFrame('plot-frames', 62, 'data-hover-invalid');
hoverFrame('plot-axis-bias', 42, 'data-hover-swap');
</script>)JS";

}  // namespace

TEST_CASE("the report of a perturbed estimate renders in headless Chromium") {
  REQUIRE(fs::exists("/usr/bin/chromium"));  // Debian package chromium (deploy/packages.txt)
  const fs::path dir = fs::absolute("report_artifacts");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto truth = walking_truth(kFrames, kStature);
  write_dataset(dir / "dataset", truth, kStature);
  write_estimates(dir / "estimate.csv", perturbed(truth));

  const std::string eval = std::string(HULLPOSE_EVAL_EXE) + " --gt '" + (dir / "dataset").string() +
                           "' --est '" + (dir / "estimate.csv").string() + "' --report '" +
                           (dir / "report").string() + "' > '" + (dir / "table.txt").string() + "'";
  REQUIRE(std::system(eval.c_str()) == 0);
  const fs::path html = dir / "report" / "report.html";
  REQUIRE(fs::exists(html));
  INFO(slurp(dir / "table.txt"));

  const fs::path png = dir / "screenshot.png";
  const std::string url = "'file://" + html.string() + "'";
  INFO(slurp(dir / "screenshot.log"));
  REQUIRE(chromium("--screenshot='" + png.string() + "' --window-size=1400,2400 " + url, dir,
                   "screenshot") == 0);
  REQUIRE(chromium("--dump-dom " + url + " > '" + (dir / "dom.html").string() + "'", dir, "dom") ==
          0);

  // The page's script found ink in all five plots once laid out.
  CHECK(slurp(dir / "dom.html").find("data-plots-drawn=\"5/5\"") != std::string::npos);

  // The pointer readout: a copy of the page that moves the pointer over two frames and keeps
  // what the tooltip said.
  std::ofstream(dir / "hover.html") << slurp(html) << kHoverScript;
  REQUIRE(chromium("--dump-dom 'file://" + (dir / "hover.html").string() + "' > '" +
                       (dir / "hover-dom.html").string() + "'",
                   dir, "hover") == 0);
  const std::string hover = slurp(dir / "hover-dom.html");
  CHECK(hover.find("data-hover-invalid=\"frame 62 · invalid (pose_jump)all joints –") !=
        std::string::npos);
  CHECK(std::regex_search(
      hover, std::regex("data-hover-swap=\"frame 42 · scored, arms swappedx -?[0-9]+\\.[0-9] mm")));

  const cv::Mat shot = cv::imread(png.string(), cv::IMREAD_COLOR);
  REQUIRE(!shot.empty());
  CHECK(shot.cols == 1400);
  CHECK(shot.rows == 2400);
  cv::Scalar mean, stddev;
  cv::meanStdDev(shot, mean, stddev);
  CHECK(stddev[0] > 10);  // not a blank page

  // Each series' colour is its own; thresholds sit well above what the legend keys alone
  // (at most 18x3 or 12x12 px) would give.
  CHECK(ink(shot, colours::kAllJoints) > 1000);
  CHECK(ink(shot, colours::kHandsFeet) > 1000);
  CHECK(ink(shot, colours::kBoxLeft) > 1000);
  CHECK(ink(shot, colours::kBoxRight) > 1000);
  CHECK(ink(shot, colours::kBoxCentre) > 1000);
  CHECK(ink(shot, colours::kAxisX) > 800);
  CHECK(ink(shot, colours::kAxisY) > 800);
  CHECK(ink(shot, colours::kAxisZ) > 800);
  CHECK(ink(shot, colours::kLrCorrect) > 10000);
  CHECK(ink(shot, colours::kLrWrong) > 500);
  CHECK(ink(shot, colours::kInvalid) > 1000);
  CHECK(ink(shot, colours::kMissing) > 500);
}
