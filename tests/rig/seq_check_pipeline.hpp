#pragma once
// In place of carve -> thin -> tree -> fit in the service and fault tests: it checks that
// every view of the frame carries the frame's own sequence (seq_pattern.hpp) and reports it in
// the pose (valid + joint 0 = (seq, views, 0) when consistent; REASON_FIT_FAILED and joint 0 x
// = -1 when views of different sequences were mixed).
#include <hullpose_msg/skeleton_t.hpp>

#include "hullpose/fusion_host/frame_pipeline.hpp"
#include "seq_pattern.hpp"

namespace hullpose::testing {

class SeqCheckPipeline final : public fusion::FramePipeline {
 public:
  void process(const fusion::AssembledFrame& frame, fusion::PoseEstimate& out) override {
    bool consistent = true;
    for (const fusion::View& v : frame.views)
      consistent = consistent && read_seq_mask(*v.mask) ==
                                     (frame.trigger_seq & ((int64_t{1} << kPatternBits) - 1));
    out.fused_after_us = 0;
    out.valid = consistent;
    out.reason = consistent ? hullpose_msg::skeleton_t::REASON_OK
                            : hullpose_msg::skeleton_t::REASON_FIT_FAILED;
    for (auto& p : out.position_mm)
      p = {static_cast<float>(frame.trigger_seq % 100000), static_cast<float>(frame.views.size()),
           0.f};
    if (!consistent) out.position_mm[0][0] = -1.f;
    out.confidence.fill(consistent ? 1.f : 0.f);
    ++frames;
  }
  int frames = 0;
};

}  // namespace hullpose::testing
