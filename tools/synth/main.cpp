// hullpose-synth: renders a synthetic multi-view dataset with ground truth (synth/ renders it;
// tools/synth/README.md).
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <string>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/synth/dataset_writer.hpp"
#include "hullpose/synth/rig_gen.hpp"

namespace {

constexpr const char* kUsage = R"(usage: hullpose-synth --motion <NAME|FILE.bvh> --out DIR [options]
       hullpose-synth --rig-out FILE [--rig R]      (only write the rig file)
  --motion M        walk, run, jump, crouch, turn, wave, tpose, or a BVH file (CMU schemes A/B/C)
  --out DIR         dataset directory (created)
  --frames N        frames to render (default: the whole clip; 300 for built-in motions)
  --fps F           rig frame rate (default 30)
  --rig R           thesis8 (7 ring + 1 ceiling camera, 800x600; default), a rig file, or a ring:
                    ring:cameras=N,radius=MM,height=MM,tilt=DEG,ceiling=0|1,vfov=DEG,k1=K,width=PX,rows=PX
  --rgb             also render colour frames and background-only frames
  --rig-out FILE    also write the rig file to FILE
  --backgrounds K   background-only frames per camera with --rgb (default 10)
  --noise SPEC      faults: salt=P,pepper=P,blobs=N,holes=N,blob_px=R,calib_px=S,calib_deg=S,
                    jitter_ms=S,drop=P,dark=CAM[@FRAME]
  --flicker S       exposure flicker, relative sigma per frame (--rgb; default 0)
  --sensor-noise S  sensor noise sigma in grey levels (--rgb; default 2)
  --seed S          seed for every random choice (default 1)
  --stature MM      body size of built-in motions (default 1750; a child is about 1200)
  --speed X         tempo of built-in motions (default 1)
  --stride MM       step length of walk/run, jump height of jump (default: by stature)
  --build B         girth: slim, average, large or a factor (default average = 1)
  --clothing MM     loose clothing thickness on torso, arms and thighs (default 0)
  --bvh-mm-per-unit X   override BVH units (default: CMU units for schemes A/B, metres for C)
  --png-level L     zlib level of the PNG files, 0..9 (default 1: fast)
  --threads N       worker threads (default: all cores)
)";

// A progress bar on stderr when it is a terminal; silence otherwise (logs stay clean).
void progress(int done, int total) {
  static const bool tty = ::isatty(STDERR_FILENO) == 1;
  static int last = -1;
  if (!tty) return;
  const int pct = total > 0 ? 100 * done / total : 100;
  if (pct == last && done != total) return;
  last = pct;
  const int width = 40, fill = width * done / std::max(1, total);
  std::fprintf(stderr, "\r[%s%s] %3d%% %d/%d frames",
               std::string(static_cast<size_t>(fill), '#').c_str(),
               std::string(static_cast<size_t>(width - fill), '.').c_str(), pct, done, total);
  if (done == total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

int run(int argc, const char* const* argv) {
  using namespace hullpose::synth;
  {
    SynthConfig cfg;
    bool have_motion = false;
    std::string rig_out;
    hullpose::cli::CommandLine cl(kUsage);
    cl.option("--motion",
              [&](const std::string& v) {
                cfg.motion = v;
                have_motion = true;
              })
        .option("--out", [&](const std::string& v) { cfg.out = v; })
        .option("--frames", cfg.frames)
        .option("--fps", cfg.fps)
        .option("--rig", cfg.rig)
        .option("--rig-out", rig_out)
        .flag("--rgb", cfg.rgb)
        .option("--backgrounds", cfg.backgrounds)
        .option("--noise", [&](const std::string& v) { cfg.faults = FaultSpec::parse(v); })
        .option("--flicker", cfg.scene.flicker)
        .option("--sensor-noise", cfg.scene.noise_sigma)
        .option("--seed", cfg.seed)
        .option("--stature", cfg.motion_options.stature_mm)
        .option("--speed", cfg.motion_options.speed)
        .option("--stride", cfg.motion_options.stride_mm)
        .option("--build",
                [&](const std::string& v) {
                  cfg.body.build = std::isdigit(static_cast<unsigned char>(v[0]))
                                       ? hullpose::cli::parse_double("--build", v)
                                       : BodyShape::build_preset(v);
                })
        .option("--clothing", cfg.body.clothing_mm)
        .option("--bvh-mm-per-unit", cfg.motion_options.bvh_mm_per_unit)
        .option("--png-level", cfg.png_compression)
        .option("--threads", [](const std::string& v) {
          cv::setNumThreads(static_cast<int>(hullpose::cli::parse_integer("--threads", v)));
        });
    if (!cl.parse(argc, argv)) return 0;
    HULLPOSE_THROW_UNLESS(cfg.png_compression >= 0 && cfg.png_compression <= 9,
                          "--png-level must be 0..9");
    if (!rig_out.empty()) {
      hullpose::save_rig(rig_from_name_or_file(cfg.rig), rig_out);
      if (!have_motion) return 0;
    }
    HULLPOSE_THROW_UNLESS(have_motion, "--motion is required (see --help)");
    HULLPOSE_THROW_UNLESS(!cfg.out.empty(), "--out is required (see --help)");
    HULLPOSE_THROW_UNLESS(cfg.body.build >= 0.5 && cfg.body.build <= 2,
                          "--build must be in 0.5..2");
    HULLPOSE_THROW_UNLESS(cfg.body.clothing_mm >= 0 && cfg.body.clothing_mm <= 150,
                          "--clothing must be in 0..150 mm");
    HULLPOSE_THROW_UNLESS(cfg.backgrounds >= 0 && cfg.backgrounds <= 10000,
                          "--backgrounds must be in 0..10000");
    const SynthSummary s = write_dataset(cfg, progress);
    std::printf("hullpose-synth: %d frames x %d cameras of %s written to %s in %.1f s\n", s.frames,
                s.cameras, s.motion.c_str(), cfg.out.string().c_str(), s.seconds);
    std::printf("stature_mm: %.1f\n", s.stature_mm);
    return 0;
  }
}

}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-synth", argc, argv, run);
}
