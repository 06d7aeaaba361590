#pragma once
// Offline pipeline of the fusion host: a dataset on disk (docs/conventions.md) through the
// PosePipeline the live service runs (fusion_host/pipeline: carve -> thin -> pose tree -> fit),
// frame by frame, into the estimate file hullpose-eval reads, with per-stage timings beside it.
#include <filesystem>
#include <optional>

#include "hullpose/fusion_host/pose_pipeline.hpp"
#include "hullpose/pose/lag_smoother.hpp"

namespace hullpose::replay {

struct ReplayOptions {
  std::filesystem::path dataset;
  std::filesystem::path out;      // estimate CSV
  std::filesystem::path timings;  // per-frame stage timings CSV; default: <out>.timings.csv
  int max_frames = -1;            // all frames of meta.json when negative
  fusion::FusionOptions fusion;
  pose::HullPoseParams pose;
  // As the live service publishes (ServiceConfig::lag): by default each frame's row is written
  // once the next frame is fitted, smoothed with its neighbours; the last one as fitted.
  pose::LagParams lag;
};

struct ReplaySummary {
  int frames = 0, valid = 0;
  // Medians over all frames, milliseconds.
  double carve_ms = 0, thin_ms = 0, fusion_ms = 0, tree_ms = 0, fit_ms = 0, total_ms = 0;
  double stature_mm = 0;  // the pose stage's running estimate at the end
};

// Throws hullpose::Error on a dataset that cannot be read (rig, meta). A mask that does not decode
// (corrupt, truncated) is that camera missing for that frame, counted and logged.
ReplaySummary run_replay(const ReplayOptions& options);

// The options of `hullpose-fusion-host --replay DIR --out FILE [...]`; nullopt after printing
// the usage for --help. Throws hullpose::Error on a bad command line.
std::optional<ReplayOptions> parse_replay_args(int argc, const char* const* argv);

// `hullpose-fusion-host --replay DIR --out FILE [...]`: parses, runs, prints a one-line JSON
// summary on stdout. Returns the exit status; throws hullpose::Error on a bad command line.
int replay_cli(int argc, const char* const* argv);
bool is_replay_command(int argc, const char* const* argv);

}  // namespace hullpose::replay
