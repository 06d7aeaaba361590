#include "hullpose/camera_node/synthetic_source.hpp"

#include <algorithm>
#include <cmath>

#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/scene.hpp"

namespace hullpose::camera_node {

struct SyntheticSource::Impl {
  std::string motion_spec;
  double fps = 30;
  int frames = 0;
  int empty_frames = 30;
  uint64_t seed = 1;
  int64_t start_utime = 0;
  synth::MotionOptions motion_options;
  synth::SceneOptions scene_options;
  CameraModel camera;

  std::unique_ptr<synth::Motion> motion;
  std::unique_ptr<synth::Scene> scene;
  std::unique_ptr<synth::CameraRenderer> renderer;
  int64_t next = 0, limit = 0, t0 = 0;
  int64_t exposed_utime = -1;  // >= 0: the next grab() is a trigger's exposure
  cv::Mat image, truth;
};

SyntheticSource::SyntheticSource(const Params& params, const SourceContext& context)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.motion_spec = params.get_string("motion", "walk");
  if (m.motion_spec.size() > 4 && m.motion_spec.substr(m.motion_spec.size() - 4) == ".bvh") {
    const std::filesystem::path p(m.motion_spec);
    m.motion_spec = (p.is_absolute() ? p : context.base_dir / p).string();
  }
  m.fps = params.get_double("fps", 30.0, 0.1, 1000.0);
  m.frames = params.get_int("frames", 0, 0, 1 << 30);
  m.empty_frames = params.get_int("empty_frames", 30, 0, 100000);
  m.seed = static_cast<uint64_t>(params.get_int("seed", 1, 0, 1 << 30));
  m.start_utime = static_cast<int64_t>(params.get_double("start_utime", 0.0, 0.0, 9.2e18));
  m.motion_options.stature_mm = params.get_double("stature_mm", 1750.0, 800.0, 2500.0);
  m.scene_options.drift = params.get_double("drift", m.scene_options.drift, 0.0, 0.5);
  m.scene_options.shadow_strength =
      params.get_double("shadow_strength", m.scene_options.shadow_strength, 0.0, 1.0);
  m.scene_options.flicker = params.get_double("flicker", m.scene_options.flicker, 0.0, 0.5);
  m.scene_options.noise_sigma =
      params.get_double("noise_sigma", m.scene_options.noise_sigma, 0.0, 50.0);
  m.camera = context.camera;
  const Eigen::Vector3d centre = 0.5 * (context.volume.min_mm + context.volume.max_mm);
  m.motion_options.centre_mm = Eigen::Vector3d(centre.x(), centre.y(), context.volume.min_mm.z());
}

SyntheticSource::~SyntheticSource() = default;

std::string SyntheticSource::describe() const {
  return "synthetic camera " + std::to_string(impl_->camera.id) + " (" + impl_->motion_spec +
         ", seed " + std::to_string(impl_->seed) + ", " + std::to_string(impl_->camera.width) +
         "x" + std::to_string(impl_->camera.height) + ")";
}

void SyntheticSource::start() {
  Impl& m = *impl_;
  m.motion =
      synth::make_motion(m.motion_spec, m.motion_options);  // throws naming a bad motion or file
  const bool endless = !std::isfinite(m.motion->duration_s());
  const int clip = endless ? 0 : m.motion->frame_count(m.fps);
  HULLPOSE_THROW_UNLESS(endless || m.frames <= clip,
                        "camera " << m.camera.id << ": synthetic source: motion "
                                  << m.motion->name() << " has " << clip << " frames at " << m.fps
                                  << " fps, " << m.frames << " asked for");
  const int motion_frames = m.frames > 0 ? m.frames : clip;  // 0 with an endless motion: no limit
  m.limit = motion_frames > 0 ? m.empty_frames + motion_frames : -1;
  m.scene = std::make_unique<synth::Scene>(m.scene_options, m.seed);
  synth::BodyShape body;
  body.stature_mm = m.motion->stature_mm();
  m.renderer = std::make_unique<synth::CameraRenderer>(*m.motion, body, m.camera, *m.scene, m.fps);
  m.next = 0;
  m.exposed_utime = -1;
  m.t0 = m.start_utime > 0 ? m.start_utime : realtime_utime();
}

GrabStatus SyntheticSource::grab(Frame& frame, int /*timeout_ms*/) {
  Impl& m = *impl_;
  HULLPOSE_ASSERT(m.renderer);
  if (m.limit >= 0 && m.next >= m.limit) return GrabStatus::kEndOfStream;
  if (m.next < m.empty_frames) {
    // Background frames: the empty room at earlier times, newest last.
    m.renderer->render_background(static_cast<int>(m.empty_frames - 1 - m.next), m.image);
    m.truth.create(m.image.size(), CV_8UC1);
    m.truth.setTo(0);
  } else {
    m.renderer->render(static_cast<int>(m.next - m.empty_frames), m.image, m.truth);
  }
  frame.image = m.image;
  frame.sequence = m.next;
  frame.capture_utime =
      m.exposed_utime >= 0
          ? m.exposed_utime
          : m.t0 + static_cast<int64_t>(std::llround(static_cast<double>(m.next) * 1e6 / m.fps));
  m.exposed_utime = -1;
  ++m.next;
  return GrabStatus::kFrame;
}

void SyntheticSource::expose(int64_t trigger_seq, int64_t capture_utime) {
  Impl& m = *impl_;
  HULLPOSE_THROW_UNLESS(trigger_seq >= 0, "camera " << m.camera.id
                                                    << ": synthetic source: trigger sequence "
                                                    << trigger_seq << " is negative");
  m.next = m.empty_frames + std::min<int64_t>(trigger_seq, 1 << 30);
  m.exposed_utime = capture_utime;
}

const cv::Mat& SyntheticSource::truth() const {
  return impl_->truth;
}

void SyntheticSource::stop() {
  impl_->renderer.reset();
  impl_->scene.reset();
  impl_->motion.reset();
}

}  // namespace hullpose::camera_node
