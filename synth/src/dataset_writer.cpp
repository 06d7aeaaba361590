#include "hullpose/synth/dataset_writer.hpp"

#include <chrono>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/synth/rig_gen.hpp"

namespace hullpose::synth {

HULLPOSE_LOG_CATEGORY(Synth, "synth")

namespace {

void write_png(const std::filesystem::path& path, const cv::Mat& image,
               const std::vector<int>& params) {
  HULLPOSE_THROW_UNLESS(cv::imwrite(path.string(), image, params), path.string()
                                                                       << ": cannot write image");
}

// Everything one camera needs while frames are rendered in parallel across cameras.
struct CameraJob {
  int id;
  ViewRenderer view;
  std::unique_ptr<CameraRenderer> colour;  // with rgb only
  JointPositions joints{};
  std::vector<Primitive> primitives;
  cv::Mat mask, bgr, atlas;
  CameraJob(int id_, const CameraModel& c) : id(id_), view(c) {}
};

}  // namespace

SynthSummary write_dataset(const SynthConfig& cfg, const std::function<void(int, int)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  HULLPOSE_THROW_UNLESS(!cfg.out.empty(), "no output directory given");
  HULLPOSE_THROW_UNLESS(cfg.fps > 0 && cfg.fps <= 1000,
                        "frame rate " << cfg.fps << " must be in (0, 1000]");
  HULLPOSE_THROW_UNLESS(cfg.frames >= 0, "frame count must not be negative");
  const Rig rig = rig_from_name_or_file(cfg.rig);

  MotionOptions mo = cfg.motion_options;
  const Eigen::Vector3d vc = 0.5 * (rig.volume.min_mm + rig.volume.max_mm);
  mo.centre_mm = Eigen::Vector3d(vc.x(), vc.y(), rig.volume.min_mm.z());
  mo.build = cfg.body.build;
  const std::unique_ptr<Motion> motion = make_motion(cfg.motion, mo);
  const bool endless = !std::isfinite(motion->duration_s());
  const int clip_frames = endless ? 0 : motion->frame_count(cfg.fps);
  const int frames = cfg.frames > 0 ? cfg.frames : (endless ? 300 : clip_frames);
  HULLPOSE_THROW_UNLESS(endless || frames <= clip_frames,
                        motion->name() << " has " << clip_frames << " frames at " << cfg.fps
                                       << " fps, " << frames << " asked for");
  BodyShape body = cfg.body;
  body.stature_mm = motion->stature_mm();

  const DatasetPaths paths(cfg.out);
  std::error_code ec;
  std::filesystem::create_directories(cfg.out, ec);
  HULLPOSE_THROW_UNLESS(!ec, cfg.out.string()
                                 << ": cannot create the dataset directory: " << ec.message());
  const Rig written = perturb_calibration(rig, cfg.faults, cfg.seed);
  save_rig(written, paths.rig());
  if (!(written == rig)) save_rig(rig, cfg.out / "rig_true.yaml");

  DatasetMeta meta;
  meta.motion = motion->name();
  meta.frames = frames;
  meta.fps = cfg.fps;
  meta.seed = cfg.seed;
  meta.start_utime = cfg.start_utime;
  meta.stature_mm = motion->stature_mm();
  meta.noise = cfg.faults.describe();
  for (const auto& c : rig.cameras) meta.camera_ids.push_back(c.id);
  write_meta(paths.meta(), meta);

  std::vector<PoseRecord> truth(static_cast<size_t>(frames));
  for (int f = 0; f < frames; ++f) {
    auto& r = truth[static_cast<size_t>(f)];
    r.frame = f;
    r.utime = cfg.start_utime + static_cast<int64_t>(std::llround(f * 1e6 / cfg.fps));
    motion->sample(f / cfg.fps, r.joints);
  }
  write_ground_truth(paths.ground_truth(), truth);

  const std::unique_ptr<Scene> scene =
      cfg.rgb ? std::make_unique<Scene>(cfg.scene, cfg.seed) : nullptr;
  std::vector<std::unique_ptr<CameraJob>> jobs;
  for (const auto& c : rig.cameras) {
    std::filesystem::create_directories(paths.camera_dir(c.id), ec);
    HULLPOSE_THROW_UNLESS(!ec, paths.camera_dir(c.id).string()
                                   << ": cannot create: " << ec.message());
    jobs.push_back(std::make_unique<CameraJob>(c.id, c));
  }
  // Noisy colour frames gain little from LZ77 matching: Huffman-only is faster and smaller.
  const std::vector<int> png = {cv::IMWRITE_PNG_COMPRESSION, cfg.png_compression,
                                cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY};
  const std::vector<int> png_mask = {cv::IMWRITE_PNG_COMPRESSION, cfg.png_compression,
                                     cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_RLE};
  const int n = static_cast<int>(jobs.size());
  // Cameras in parallel; the first error (e.g. a full disk) is rethrown here, on this thread.
  auto for_each_camera = [&](const std::function<void(CameraJob&)>& work) {
    std::mutex mutex;
    std::string error;
    cv::parallel_for_(cv::Range(0, n), [&](const cv::Range& range) {
      for (int i = range.start; i < range.end; ++i) {
        try {
          work(*jobs[static_cast<size_t>(i)]);
        } catch (const std::exception& e) {
          const std::lock_guard<std::mutex> lock(mutex);
          if (error.empty()) error = e.what();
        }
      }
    });
    HULLPOSE_THROW_UNLESS(error.empty(), error);
  };
  if (scene) {
    for_each_camera([&](CameraJob& job) {
      job.colour =
          std::make_unique<CameraRenderer>(*motion, body, *rig.find(job.id), *scene, cfg.fps);
      for (int k = 0; k < cfg.backgrounds; ++k) {
        job.colour->render_background(k, job.bgr);
        write_png(paths.background(job.id, k), job.bgr, png);
      }
    });
  }

  // Without trigger jitter every camera sees the same pose and shadows: compute them once.
  const bool shared_pose = cfg.faults.jitter_ms <= 0;
  JointPositions joints{};
  std::vector<Primitive> primitives;
  cv::Mat atlas;
  for (int f = 0; f < frames; ++f) {
    const double t = f / cfg.fps;
    if (shared_pose) {
      motion->sample(t, joints);
      pose_avatar(body, joints, primitives);
      if (scene) scene->shadows(primitives, atlas);
    }
    for_each_camera([&](CameraJob& job) {
      if (frame_dropped(cfg.faults, cfg.seed, job.id, f)) return;  // the camera sent nothing
      const double tc = t + trigger_offset_s(cfg.faults, cfg.seed, job.id, f);
      const std::vector<Primitive>* prims = &primitives;
      const cv::Mat* shadow = &atlas;
      if (!shared_pose) {
        motion->sample(tc, job.joints);
        pose_avatar(body, job.joints, job.primitives);
        if (scene) scene->shadows(job.primitives, job.atlas);
        prims = &job.primitives;
        shadow = &job.atlas;
      }
      if (scene)
        job.colour->render_posed(f, tc, *prims, *shadow, job.bgr, job.mask);
      else
        job.view.render_mask(*prims, job.mask);
      if (camera_dark(cfg.faults, job.id, f)) {
        job.mask.setTo(0);
        if (scene) job.colour->render_dark(f, job.bgr);
      } else if (cfg.faults.silhouette_noise()) {
        corrupt_silhouette(job.mask, cfg.faults, cfg.seed, job.id, f);
      }
      write_png(paths.mask(job.id, f), job.mask, png_mask);
      if (scene) write_png(paths.rgb(job.id, f), job.bgr, png);
    });
    if (progress) progress(f + 1, frames);
  }

  SynthSummary s;
  s.frames = frames;
  s.cameras = n;
  s.stature_mm = motion->stature_mm();
  s.motion = motion->name();
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  HULLPOSE_LOG(Synth, Debug) << cfg.out.string() << ": " << frames << " frames x " << n
                             << " cameras of " << motion->name() << " in " << s.seconds << " s";
  return s;
}

}  // namespace hullpose::synth
