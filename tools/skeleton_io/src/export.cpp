#include "hullpose/skeleton_io/export.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/skeleton_io/bvh.hpp"
#include "hullpose/skeleton_io/gaps.hpp"
#include "hullpose/skeleton_io/markers.hpp"

namespace hullpose::skeleton_io {
namespace {

// BVH has no "no data" value: a missing frame holds the nearest earlier pose (the first
// measured one for a leading gap); the flagged ranges are in the summary and the gaps file.
void write_bvh(const std::string& path, const Take& take, const GapReport& gaps) {
  const BvhSkeleton skeleton(subject_bone_lengths(take.frames));
  std::ofstream out(path);
  HULLPOSE_THROW_UNLESS(out.good(), path << ": cannot write");
  skeleton.write_header(out, static_cast<int>(take.frames.size()), 1.0 / take.fps);
  size_t held = 0;
  while (held < take.frames.size() && gaps.state[held] == FrameState::Missing) ++held;
  std::vector<double> channels;
  std::string line;
  for (size_t f = 0; f < take.frames.size(); ++f) {
    if (gaps.state[f] != FrameState::Missing) held = f;
    skeleton.solve(take.frames[held].joints, channels);
    BvhSkeleton::format_line(channels, line);
    out << line;
  }
  HULLPOSE_THROW_UNLESS(out.good(), path << ": write failed");
}

}  // namespace

std::string export_take(const ExportOptions& o) {
  HULLPOSE_THROW_UNLESS(!o.input.empty(), "--in: a take to export is required");
  HULLPOSE_THROW_UNLESS(!o.bvh.empty() || !o.trc.empty() || !o.c3d.empty(),
                        "nothing to write: give --bvh, --trc and/or --c3d");
  HULLPOSE_THROW_UNLESS(std::isfinite(o.max_gap_ms) && o.max_gap_ms >= 0 && o.max_gap_ms <= 10'000,
                        "--max-gap-ms must be in [0, 10000], got " << o.max_gap_ms);
  Take take = read_take(o.input, o.fps, o.channel);
  const int max_fill = static_cast<int>(std::floor(o.max_gap_ms * take.fps / 1000.0 + 1e-9));
  const GapReport gaps = fill_gaps(take.frames, max_fill);
  HULLPOSE_THROW_UNLESS(gaps.missing < static_cast<int>(take.frames.size()),
                        o.input << ": no valid frame in the take");
  if (!o.bvh.empty()) write_bvh(o.bvh, take, gaps);
  if (!o.trc.empty()) write_trc(o.trc, take, gaps);
  if (!o.c3d.empty()) write_c3d(o.c3d, take, gaps);

  nlohmann::json summary = {{"input", o.input},
                            {"frames", take.frames.size()},
                            {"fps", take.fps},
                            {"filled_frames", gaps.filled},
                            {"missing_frames", gaps.missing},
                            {"max_fill_frames", max_fill},
                            {"inserted_sequences", take.inserted},
                            {"malformed_messages", take.malformed}};
  // Which bone lengths the BVH hierarchy has: the held body model's, or (none held) the median.
  const int32_t model = held_model_version(take.frames);
  int64_t held = 0, provisional = 0;
  for (const SkeletonFrame& f : take.frames)
    if (f.valid) (f.model_version == model && model > 0 ? held : provisional) += 1;
  summary["bvh_bone_lengths"] = model > 0 ? "held body model" : "median of the valid frames";
  summary["held_model_version"] = model;
  summary["held_model_frames"] = held;
  summary["other_valid_frames"] = provisional;
  nlohmann::json ranges = nlohmann::json::array();
  for (const auto& [first, last] : gaps.missing_ranges) ranges.push_back({first, last});
  summary["missing_ranges"] = ranges;
  if (!o.gaps_json.empty()) {
    std::ofstream out(o.gaps_json);
    HULLPOSE_THROW_UNLESS(out.good(), o.gaps_json << ": cannot write");
    nlohmann::json states = nlohmann::json::array();
    for (FrameState s : gaps.state)
      states.push_back(s == FrameState::Measured ? "measured"
                       : s == FrameState::Filled ? "filled"
                                                 : "missing");
    out << nlohmann::json{{"summary", summary}, {"frames", states}}.dump() << "\n";
  }
  return summary.dump();
}

}  // namespace hullpose::skeleton_io
