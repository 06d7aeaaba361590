// hullpose-synth: renders a synthetic multi-view dataset with ground truth (tools/synth/README.md).
#include <unistd.h>

#include <charconv>
#include <cstdio>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <string>

#include "hullpose/common/check.hpp"
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
  --threads N       worker threads (default: all cores)
)";

double to_number(const std::string& flag, const std::string& text) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  HULLPOSE_THROW_UNLESS(ec == std::errc() && end == text.data() + text.size() && std::isfinite(v),
                        flag << ": '" << text << "' is not a number");
  return v;
}

// A progress bar on stderr when it is a terminal; silence otherwise (logs stay clean).
void progress(int done, int total) {
  static const bool tty = ::isatty(STDERR_FILENO) == 1;
  static int last = -1;
  if (!tty) return;
  const int pct = total > 0 ? 100 * done / total : 100;
  if (pct == last && done != total) return;
  last = pct;
  const int width = 40, fill = width * done / std::max(1, total);
  std::fprintf(stderr, "\r[%s%s] %3d%% %d/%d frames", std::string(static_cast<size_t>(fill), '#').c_str(),
               std::string(static_cast<size_t>(width - fill), '.').c_str(), pct, done, total);
  if (done == total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hullpose::synth;
  try {
    SynthConfig cfg;
    bool have_motion = false;
    std::string rig_out;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        HULLPOSE_THROW_UNLESS(i + 1 < argc, a << " needs a value");
        return argv[++i];
      };
      if (a == "-h" || a == "--help") {
        std::cout << kUsage;
        return 0;
      } else if (a == "--motion") {
        cfg.motion = value();
        have_motion = true;
      } else if (a == "--out") {
        cfg.out = value();
      } else if (a == "--frames") {
        cfg.frames = static_cast<int>(to_number(a, value()));
      } else if (a == "--fps") {
        cfg.fps = to_number(a, value());
      } else if (a == "--rig") {
        cfg.rig = value();
      } else if (a == "--rig-out") {
        rig_out = value();
      } else if (a == "--rgb") {
        cfg.rgb = true;
      } else if (a == "--backgrounds") {
        cfg.backgrounds = static_cast<int>(to_number(a, value()));
      } else if (a == "--noise") {
        cfg.faults = FaultSpec::parse(value());
      } else if (a == "--flicker") {
        cfg.scene.flicker = to_number(a, value());
      } else if (a == "--sensor-noise") {
        cfg.scene.noise_sigma = to_number(a, value());
      } else if (a == "--seed") {
        const std::string s = value();
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), cfg.seed);
        HULLPOSE_THROW_UNLESS(ec == std::errc() && end == s.data() + s.size(), "--seed: '" << s << "' is not an integer");
      } else if (a == "--stature") {
        cfg.motion_options.stature_mm = to_number(a, value());
      } else if (a == "--speed") {
        cfg.motion_options.speed = to_number(a, value());
      } else if (a == "--stride") {
        cfg.motion_options.stride_mm = to_number(a, value());
      } else if (a == "--build") {
        const std::string b = value();
        cfg.body.build = std::isdigit(static_cast<unsigned char>(b[0])) ? to_number(a, b) : BodyShape::build_preset(b);
      } else if (a == "--clothing") {
        cfg.body.clothing_mm = to_number(a, value());
      } else if (a == "--bvh-mm-per-unit") {
        cfg.motion_options.bvh_mm_per_unit = to_number(a, value());
      } else if (a == "--threads") {
        cv::setNumThreads(static_cast<int>(to_number(a, value())));
      } else {
        HULLPOSE_THROW("unknown option '" << a << "' (see --help)");
      }
    }
    if (!rig_out.empty()) {
      hullpose::save_rig(rig_from_name_or_file(cfg.rig), rig_out);
      if (!have_motion) return 0;
    }
    HULLPOSE_THROW_UNLESS(have_motion, "--motion is required (see --help)");
    HULLPOSE_THROW_UNLESS(!cfg.out.empty(), "--out is required (see --help)");
    HULLPOSE_THROW_UNLESS(cfg.body.build >= 0.5 && cfg.body.build <= 2, "--build must be in 0.5..2");
    HULLPOSE_THROW_UNLESS(cfg.body.clothing_mm >= 0 && cfg.body.clothing_mm <= 150, "--clothing must be in 0..150 mm");
    HULLPOSE_THROW_UNLESS(cfg.backgrounds >= 0 && cfg.backgrounds <= 10000, "--backgrounds must be in 0..10000");
    const SynthSummary s = write_dataset(cfg, progress);
    std::printf("hullpose-synth: %d frames x %d cameras of %s written to %s in %.1f s\n", s.frames, s.cameras,
                s.motion.c_str(), cfg.out.string().c_str(), s.seconds);
    std::printf("stature_mm: %.1f\n", s.stature_mm);
    return 0;
  } catch (const hullpose::Error& e) {
    std::fprintf(stderr, "hullpose-synth: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {  // cv::Exception, std::filesystem::filesystem_error, ...
    std::fprintf(stderr, "hullpose-synth: error: %s\n", e.what());
    return 2;
  }
}
