#include "hullpose/eval/cli.hpp"

#include <filesystem>
#include <optional>
#include <string>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/eval/consistency.hpp"
#include "hullpose/eval/consistency_report.hpp"
#include "hullpose/eval/report.hpp"

namespace hullpose::eval {
namespace {

constexpr const char* kUsage =
    "usage: hullpose-eval --gt DIR --est FILE [--json] [--report DIR] [--tolerance-px 2] "
    "[--show-frames F,F,...]\n"
    "  --gt DIR       dataset directory (meta.json, ground_truth.csv); without ground_truth.csv "
    "the\n"
    "                 estimate is scored against the silhouettes (consistency.hpp)\n"
    "  --est FILE     estimate CSV (frame,valid,reason,HeadTop_x,...,RToe_z)\n"
    "  --json         print one JSON object instead of the table\n"
    "  --report DIR   also write DIR/report.html (the plots) and DIR/per_frame.csv\n"
    "  --tolerance-px, --show-frames: without ground truth, how far outside a silhouette a bone "
    "point\n"
    "                 may project, and the frames drawn in the report (default: 4 spread over the "
    "valid)\n";

struct Options {
  std::string gt, est, report;
  bool json = false;
  ConsistencyOptions consistency;
};

// Empty when --help was asked for.
std::optional<Options> parse(int argc, const char* const* argv, std::ostream& out) {
  Options o;
  cli::CommandLine cl(kUsage);
  cl.option("--gt", o.gt)
      .option("--est", o.est)
      .option("--report", o.report)
      .flag("--json", o.json)
      .option("--tolerance-px", o.consistency.tolerance_px)
      .option("--show-frames", [&](const std::string& v) {
        for (size_t start = 0; start <= v.size();) {
          const size_t comma = v.find(',', start);
          o.consistency.show_frames.push_back(static_cast<int>(cli::parse_integer(
              "--show-frames", std::string_view(v).substr(start, comma - start))));
          if (comma == std::string::npos) break;
          start = comma + 1;
        }
      });
  if (!cl.parse(argc, argv, out)) return std::nullopt;
  HULLPOSE_THROW_UNLESS(!o.gt.empty(), "--gt DIR is required");
  HULLPOSE_THROW_UNLESS(!o.est.empty(), "--est FILE is required");
  return o;
}

// A real capture: no ground truth, so the estimate is checked against the silhouettes.
int run_consistency(const Options& o, std::ostream& out) {
  const std::vector<PoseRecord> estimates = read_estimates(o.est);
  const ConsistencyResult result = evaluate_consistency(o.gt, estimates, o.consistency);
  if (o.json)
    write_consistency_json(out, result);
  else
    write_consistency_table(out, result, o.gt, o.est);
  if (!o.report.empty()) {
    const auto page =
        write_consistency_report(o.report, o.gt, o.est, estimates, result, o.consistency);
    if (!o.json) out << "\nreport: " << page.string() << '\n';
  }
  return 0;
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out) {
  const std::optional<Options> parsed = parse(argc, argv, out);
  if (!parsed) return 0;
  const Options& o = *parsed;
  HULLPOSE_THROW_UNLESS(std::filesystem::is_directory(o.gt), o.gt << ": not a dataset directory");
  // A dataset without ground truth (a real capture): scored against its silhouettes.
  const DatasetPaths paths(o.gt);
  if (std::filesystem::exists(paths.meta()) && !std::filesystem::exists(paths.ground_truth()))
    return run_consistency(o, out);
  const EvalResult result = evaluate_files(o.gt, o.est);
  const ReportSource source{o.gt, o.est, read_meta(DatasetPaths(o.gt).meta()).motion};
  if (o.json)
    write_json(out, result);
  else
    write_table(out, result, source);
  if (!o.report.empty()) {
    const auto path = write_html_report(o.report, result, source);
    write_per_frame_csv(std::filesystem::path(o.report) / "per_frame.csv", result);
    if (!o.json) out << "\nreport: " << path.string() << '\n';
  }
  return 0;
}

}  // namespace hullpose::eval
