#include "hullpose/eval/cli.hpp"

#include <optional>
#include <string>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/eval/report.hpp"

namespace hullpose::eval {
namespace {

constexpr const char* kUsage =
    "usage: hullpose-eval --gt DIR --est FILE [--json] [--report DIR]\n"
    "  --gt DIR       dataset directory (meta.json, ground_truth.csv)\n"
    "  --est FILE     estimate CSV (frame,valid,reason,HeadTop_x,...,RToe_z)\n"
    "  --json         print one JSON object instead of the table\n"
    "  --report DIR   also write DIR/report.html (the plots) and DIR/per_frame.csv\n";

struct Options {
  std::string gt, est, report;
  bool json = false;
};

// Empty when --help was asked for.
std::optional<Options> parse(int argc, const char* const* argv) {
  Options o;
  cli::CommandLine cl(kUsage);
  cl.option("--gt", o.gt).option("--est", o.est).option("--report", o.report).flag("--json", o.json);
  if (!cl.parse(argc, argv)) return std::nullopt;
  HULLPOSE_THROW_UNLESS(!o.gt.empty(), "--gt DIR is required");
  HULLPOSE_THROW_UNLESS(!o.est.empty(), "--est FILE is required");
  return o;
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  Options o;
  try {
    const std::optional<Options> parsed = parse(argc, argv);
    if (!parsed) {
      out << kUsage;
      return 0;
    }
    o = *parsed;
  } catch (const Error& e) {
    err << "hullpose-eval: error: " << e.what() << '\n' << kUsage;
    return 2;
  }
  try {
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
  } catch (const Error& e) {
    err << "hullpose-eval: error: " << e.what() << '\n';
    return 2;
  }
}

}  // namespace hullpose::eval
