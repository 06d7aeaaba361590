// Fuzz target: the BVH parser (synth/bvh.hpp parse_bvh) and the mapping onto the joint model
// (make_bvh_motion, sampled) return or throw hullpose::Error, for any text.
#include <cstdint>
#include <string_view>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/bvh.hpp"
#include "hullpose/synth/motion.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const hullpose::synth::BvhClip clip =
        hullpose::synth::parse_bvh({reinterpret_cast<const char*>(data), size}, "fuzz.bvh");
    auto motion = hullpose::synth::make_bvh_motion(clip, {});
    hullpose::JointPositions q;
    motion->sample(0.0, q);
    motion->sample(1e9, q);
  } catch (const hullpose::Error&) {
  }
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  const std::string_view clip =
      "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition "
      "Zrotation Xrotation Yrotation\n"
      "  JOINT LeftUpLeg\n  {\n    OFFSET 3 0 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
      "    JOINT LeftLeg\n    {\n      OFFSET 0 -17 0\n      CHANNELS 3 Zrotation Xrotation "
      "Yrotation\n"
      "      End Site\n      {\n        OFFSET 0 -16 0\n      }\n    }\n  }\n"
      "  JOINT Spine\n  {\n    OFFSET 0 5 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
      "    JOINT Head\n    {\n      OFFSET 0 20 0\n      CHANNELS 3 Zrotation Xrotation Yrotation\n"
      "      End Site\n      {\n        OFFSET 0 8 0\n      }\n    }\n  }\n}\n"
      "MOTION\nFrames: 2\nFrame Time: 0.0333333\n"
      "0 35 0 0 0 0 0 0 0 10 0 0 0 0 0 0 0 0\n1 35 0 5 0 0 0 0 0 12 0 0 0 0 0 0 0 0\n";
  return {{clip.begin(), clip.end()}};
}
