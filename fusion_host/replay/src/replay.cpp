#include "hullpose/replay/replay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/dataset.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::replay {

HULLPOSE_LOG_CATEGORY(Replay, "replay")

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

ReplaySummary run_replay(const ReplayOptions& options) {
  const DatasetPaths paths(options.dataset);
  const Rig rig = load_rig(paths.rig());
  const DatasetMeta meta = read_meta(paths.meta());
  const int frames =
      options.max_frames >= 0 ? std::min(options.max_frames, meta.frames) : meta.frames;

  Counters counters;
  fusion::PosePipeline pipeline(rig, options.fusion, options.pose, &counters);
  EstimateWriter writer(options.out);
  const std::filesystem::path timings_path =
      options.timings.empty() ? std::filesystem::path(options.out.string() + ".timings.csv")
                              : options.timings;
  std::ofstream timings(timings_path);
  HULLPOSE_THROW_UNLESS(timings, timings_path << ": cannot open for writing");
  timings << "frame,valid,reason,carve_ms,cleanup_ms,thin_ms,fusion_ms,tree_ms,fit_ms,total_ms,"
             "skeleton_voxels,"
             "stature_mm\n";

  std::vector<cv::Mat> views(rig.cameras.size());
  ReplaySummary summary;
  std::vector<double> carve, thin, fused, tree, fit, total;
  PoseRecord record, held;  // held: the frame the lag holds (options.lag)
  pose::LagSmoother lag(options.lag);
  for (int f = 0; f < frames; ++f) {
    for (size_t c = 0; c < rig.cameras.size(); ++c) {
      const std::filesystem::path mask = paths.mask(rig.cameras[c].id, f);
      if (!std::filesystem::exists(mask)) {
        views[c].release();  // the camera sent nothing this frame
        continue;
      }
      views[c] = cv::imread(mask.string(), cv::IMREAD_GRAYSCALE);
      if (views[c].empty()) {  // corrupt or truncated: the camera is missing for this frame
        counters.add("replay.mask_unreadable");
        HULLPOSE_LOG(Replay, Warn)
            << mask.string() << ": unreadable (corrupt or truncated): camera " << rig.cameras[c].id
            << " missing in frame " << f;
        continue;
      }
      HULLPOSE_THROW_UNLESS(
          views[c].cols == rig.cameras[c].width && views[c].rows == rig.cameras[c].height,
          mask << ": the mask is " << views[c].cols << "x" << views[c].rows << ", camera "
               << rig.cameras[c].id << " of the rig is " << rig.cameras[c].width << "x"
               << rig.cameras[c].height);
    }
    const fusion::FrameOutcome& outcome = pipeline.process(views);
    const fusion::FusionResult& hull = *outcome.hull;
    const pose::PoseEstimate& pose = *outcome.pose;
    record.frame = f;
    record.valid = outcome.valid;
    record.reason = outcome.reason;
    record.model_version = pose.model_version;
    record.joints = pose.joints_mm;
    if (options.lag.frames == 0) {
      writer.write(record);
    } else {
      if (const JointPositions* joints = lag.push(record.joints, record.valid, true)) {
        held.joints = *joints;
        writer.write(held);
      }
      std::swap(held, record);
    }

    const double tree_ms = pose.tree_us * 1e-3, fit_ms = pose.fit_us * 1e-3;
    carve.push_back(hull.timings.carve_ms);
    thin.push_back(hull.timings.thin_ms);
    fused.push_back(hull.timings.total_ms);
    tree.push_back(tree_ms);
    fit.push_back(fit_ms);
    total.push_back(hull.timings.total_ms + tree_ms + fit_ms);
    timings << f << ',' << pose.valid << ',' << int{record.reason} << ',' << hull.timings.carve_ms
            << ',' << hull.timings.cleanup_ms << ',' << hull.timings.thin_ms << ','
            << hull.timings.total_ms << ',' << tree_ms << ',' << fit_ms << ',' << total.back()
            << ',' << hull.skeleton_voxels.size() << ',' << pose.stature_mm << '\n';
    summary.valid += pose.valid;
    if (!pose.valid) {
      HULLPOSE_LOG(Replay, Debug) << "frame " << f << ": " << pose.detail;
    }
  }
  if (const JointPositions* joints = lag.release()) {
    held.joints = *joints;
    writer.write(held);
  }
  writer.flush();
  for (const auto& [name, count] : counters.snapshot())
    if (name == "replay.mask_unreadable" && count > 0) {
      HULLPOSE_LOG(Replay, Warn) << count
                                 << " unreadable masks: those cameras were missing in those frames";
    }
  summary.frames = frames;
  summary.carve_ms = median(carve);
  summary.thin_ms = median(thin);
  summary.fusion_ms = median(fused);
  summary.tree_ms = median(tree);
  summary.fit_ms = median(fit);
  summary.total_ms = median(total);
  summary.stature_mm = pipeline.estimator().last().stature_mm;
  return summary;
}

bool is_replay_command(int argc, const char* const* argv) {
  return std::any_of(argv + 1, argv + argc,
                     [](const char* a) { return std::string_view(a) == "--replay"; });
}

std::optional<ReplayOptions> parse_replay_args(int argc, const char* const* argv) {
  ReplayOptions options;
  options.fusion.resolution = 128;
  std::string dataset, out, timings;
  cli::CommandLine line(
      "usage: hullpose-fusion-host --replay DIR --out FILE [--resolution N] [--frames N] "
      "[--threads N]\n"
      "         [--backend auto|cpu|cuda] [--skeletoniser ck3|d6i1d] [--curve-rule "
      "ck3|isthmus|endvoxel]\n"
      "         [--timings FILE] [--pose bottom-up|track] [--smooth-hz HZ (0: off)] [--lag-frames "
      "1|0]\n"
      "Runs the fusion host's stages offline over a dataset (docs/conventions.md) and writes the "
      "estimates\n"
      "hullpose-eval reads; --timings defaults to FILE.timings.csv; --curve-rule is CK3's curve "
      "constraint\n"
      "(fusion_host/pose/README.md compares them); --pose track (default) tracks the subject's "
      "body\n"
      "model on the hull with the per-frame bottom-up path for acquisition and recovery, "
      "bottom-up\n"
      "is that path alone; --smooth-hz puts a One Euro filter with that cut-off at rest on the "
      "published\n"
      "joints (fusion_host/pose/one_euro.hpp says what it costs); --lag-frames 1 (default) writes "
      "each frame\n"
      "smoothed with the next, as the live host publishes it (fusion_host/pose/lag_smoother.hpp), "
      "0 as fitted.\n");
  line.option("--replay", dataset)
      .option("--out", out)
      .option("--timings", timings)
      .option("--resolution", options.fusion.resolution)
      .option("--frames", options.max_frames)
      .option("--threads", options.fusion.threads)
      .option("--skeletoniser",
              [&](const std::string& v) {
                HULLPOSE_THROW_UNLESS(v == "ck3" || v == "d6i1d",
                                      "--skeletoniser: expected ck3 or d6i1d, got '" << v << "'");
                options.fusion.skeletoniser =
                    v == "ck3" ? fusion::Skeletoniser::kCk3 : fusion::Skeletoniser::kD6i1d;
              })
      .option("--backend",
              [&](const std::string& v) { options.fusion.backend = gpu::parse_backend(v); })
      .option("--pose", [&](const std::string& v) { options.pose.mode = pose::parse_pose_mode(v); })
      .option("--smooth-hz",
              [&](const std::string& v) {
                const double hz = cli::parse_double("--smooth-hz", v);
                HULLPOSE_THROW_UNLESS(hz >= 0,
                                      "--smooth-hz must not be negative (0: off), got " << v);
                options.pose.filter.min_cutoff_hz = hz;
              })
      .option("--lag-frames",
              [&](const std::string& v) { options.lag.frames = pose::parse_lag_frames(v); })
      .option("--curve-rule", [&](const std::string& v) {
        if (v == "ck3") {
          options.fusion.curve_rule = thin::CurveRule::kCk3;
        } else if (v == "isthmus") {
          options.fusion.curve_rule = thin::CurveRule::kIsthmus;
        } else if (v == "endvoxel") {
          options.fusion.curve_rule = thin::CurveRule::kEndVoxel;
        } else {
          HULLPOSE_THROW("--curve-rule: expected ck3, isthmus or endvoxel, got '" << v << "'");
        }
      });
  if (!line.parse(argc, argv)) return std::nullopt;
  HULLPOSE_THROW_UNLESS(!dataset.empty() && !out.empty(),
                        "--replay DIR and --out FILE are both needed");
  options.dataset = dataset;
  options.out = out;
  options.timings = timings;
  return options;
}

int replay_cli(int argc, const char* const* argv) {
  const std::optional<ReplayOptions> options = parse_replay_args(argc, argv);
  if (!options) return 0;
  const ReplaySummary s = run_replay(*options);
  using Json = nlohmann::ordered_json;
  // Divided by a power of ten, so that the printed number is the short one.
  const auto round = [](double v, double per_unit) { return std::round(v * per_unit) / per_unit; };
  const Json summary{{"frames", s.frames},
                     {"valid", s.valid},
                     {"stature_mm", round(s.stature_mm, 10)},
                     {"median_ms",
                      {{"carve", round(s.carve_ms, 1000)},
                       {"thin", round(s.thin_ms, 1000)},
                       {"fusion", round(s.fusion_ms, 1000)},
                       {"tree", round(s.tree_ms, 1000)},
                       {"fit", round(s.fit_ms, 1000)},
                       {"total", round(s.total_ms, 1000)}}}};
  std::cout << summary.dump() << '\n';
  return 0;
}

}  // namespace hullpose::replay
