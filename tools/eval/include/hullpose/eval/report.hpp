#pragma once
// The ways hullpose-eval presents an EvalResult: one JSON object, a text table, a per-frame
// CSV, and a self-contained HTML page with the plots of thesis chapter 6.4.
#include <filesystem>
#include <ostream>
#include <string>

#include "hullpose/eval/metrics.hpp"

namespace hullpose::eval {

// Where the numbers came from, for the report's heading.
struct ReportSource {
  std::string dataset;   // ground-truth directory
  std::string estimate;  // estimate file
  std::string motion;    // meta.json motion
};

// One JSON object on one line; NaN (nothing to average) is written as null.
void write_json(std::ostream& out, const EvalResult& result);
void write_table(std::ostream& out, const EvalResult& result, const ReportSource& source);
// One row per ground-truth frame: frame,status,reason,mean_mm,extremity_mm,hands_feet_mm,
// abs_{x,y,z}_mm,bias_{x,y,z}_mm,lr_arms_correct,lr_legs_correct,stature_gt_mm,stature_est_mm
// (empty fields where the frame was not scored).
void write_per_frame_csv(const std::filesystem::path& path, const EvalResult& result);

// The report's series colours (#rrggbb), one per kind of mark, so that a screenshot can be
// checked for each plot's ink.
namespace colours {
inline constexpr const char* kAllJoints = "#1d4ed8";  // error per frame, all joints
inline constexpr const char* kHandsFeet = "#f97316";  // error per frame, hands and feet
inline constexpr const char* kBoxLeft = "#93c5fd";    // box fill, left-side joints
inline constexpr const char* kBoxRight = "#fca5a5";   // box fill, right-side joints
inline constexpr const char* kBoxCentre = "#d4d4d8";  // box fill, central joints
inline constexpr const char* kAxisX = "#e11d48";
inline constexpr const char* kAxisY = "#16a34a";
inline constexpr const char* kAxisZ = "#7c3aed";
inline constexpr const char* kLrCorrect = "#4ade80";  // frame strip: scored, left/right correct
inline constexpr const char* kLrWrong = "#b91c1c";    // frame strip: scored, left/right swapped
inline constexpr const char* kInvalid = "#fbbf24";    // frame strip and bands: estimate invalid
inline constexpr const char* kMissing = "#a8a29e";    // frame strip and bands: no estimate row
}  // namespace colours

// Writes DIR/report.html (creating DIR) and returns its path. No network needed to view it:
// the plots are inline SVG, the one script only marks the page once the plots are laid out
// (<body data-plots-drawn="N/N">).
std::filesystem::path write_html_report(const std::filesystem::path& dir, const EvalResult& result,
                                        const ReportSource& source);

}  // namespace hullpose::eval
