#pragma once
// hullpose-export's job as a function (so tests call it without a process): read a take, fill
// short gaps, write the formats asked for, report what was filled and what is flagged.
#include <string>

namespace hullpose::skeleton_io {

struct ExportOptions {
  std::string input, bvh, trc, c3d, gaps_json;
  std::string channel = "SKELETON";
  double fps = 30;          // estimate CSV only (a log has its own clock)
  double max_gap_ms = 200;  // invalid runs up to this long between fresh poses are interpolated
};

// Returns a one-line JSON summary (frames, fps, filled, missing, files). Throws hullpose::Error.
std::string export_take(const ExportOptions& options);

}  // namespace hullpose::skeleton_io
