#pragma once
// The fusion pipeline as the live service sees it: the assembled views of one trigger instant
// in, one pose out. The real one is carve -> thin -> pose tree -> fit (fusion_host/carve, thin,
// pose); tests plug in their own.
#include <array>
#include <cstdint>
#include <vector>

#include "hullpose/common/joints.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/fusion_host/frame_assembler.hpp"

namespace hullpose::fusion {

struct PoseEstimate {
  bool valid = false;
  int8_t reason = 0;  // skeleton_t::REASON_*
  std::array<std::array<float, 3>, kNumJoints> position_mm{};
  std::array<float, kNumJoints> confidence{};
  int32_t model_version = 0;  // skeleton_t::model_version
  // When carving + thinning finished, microseconds after process() began; -1: not reached.
  int64_t fused_after_us = -1;
  // The carved hull of this frame (after clean-up) and its grid, when the pipeline has one; they
  // live in the pipeline until its next process() (the HULL channel reads them).
  const BitGrid* hull = nullptr;
  const VoxelGridSpec* hull_grid = nullptr;
};

class FramePipeline {
 public:
  virtual ~FramePipeline() = default;
  // frame has at least min_cameras views. Must not throw on bad data: report it in `out`.
  virtual void process(const AssembledFrame& frame, PoseEstimate& out) = 0;
};

// The frame's views laid out by camera index (Rig::cameras order), as carving takes them: the
// mask of each camera that sent one, an empty Mat for the others; rois likewise. Reuses the
// vectors (cv::Mat headers share the assembler's buffers: no pixel copies, no allocation once
// the vectors have their size).
void views_by_camera_index(const AssembledFrame& frame, size_t num_cameras,
                           std::vector<cv::Mat>& masks, std::vector<PixelRoi>& rois);

}  // namespace hullpose::fusion
