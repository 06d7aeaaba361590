#pragma once
// The fusion pipeline as the live service sees it: the assembled views of one trigger instant
// in, one pose out. The real one is carve -> thin -> pose tree -> fit (fusion_host/carve, thin,
// pose); tests plug in their own.
#include <array>
#include <cstdint>

#include "hullpose/common/joints.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/fusion_host/frame_assembler.hpp"

namespace hullpose::fusion {

struct PoseEstimate {
  bool valid = false;
  int8_t reason = 0;                                   // skeleton_t::REASON_*
  std::array<std::array<float, 3>, kNumJoints> position_mm{};
  std::array<float, kNumJoints> confidence{};
  int64_t fused_utime = 0;  // when carving + thinning finished (realtime); 0: not reached
};

class FramePipeline {
 public:
  virtual ~FramePipeline() = default;
  // frame has at least min_cameras views. Must not throw on bad data: report it in `out`.
  virtual void process(const AssembledFrame& frame, PoseEstimate& out) = 0;
};

}  // namespace hullpose::fusion
