#include "support/cmu_scene.hpp"

#include <filesystem>

#include "hullpose/synth/avatar.hpp"
#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/render.hpp"
#include "hullpose/synth/rig_gen.hpp"

namespace hullpose::fusion::testing {

CmuFrames render_cmu_55_01(int count, const std::string& rig) {
  constexpr double kFps = 30;
  CmuFrames out;
  out.rig = synth::rig_from_name_or_file(rig);
  synth::MotionOptions options;
  options.centre_mm = (out.rig.volume.min_mm + out.rig.volume.max_mm) / 2;
  options.centre_mm.z() = 0;
  const auto motion = synth::load_bvh_motion(
      std::filesystem::path(HULLPOSE_SHARED_DIR) / "data/mocap/55_01.bvh", options);
  synth::BodyShape body;
  body.stature_mm = motion->stature_mm();
  std::vector<synth::ViewRenderer> renderers;
  for (const CameraModel& c : out.rig.cameras) renderers.emplace_back(c);
  const int total = motion->frame_count(kFps);
  JointPositions joints;
  std::vector<synth::Primitive> primitives;
  for (int i = 0; i < count; ++i) {
    const int f = static_cast<int>((i + 0.5) * total / count);
    motion->sample(f / kFps, joints);
    synth::pose_avatar(body, joints, primitives);
    out.frames.push_back(f);
    auto& views = out.views.emplace_back(out.rig.cameras.size());
    for (size_t c = 0; c < renderers.size(); ++c) renderers[c].render_mask(primitives, views[c]);
  }
  return out;
}

}  // namespace hullpose::fusion::testing
