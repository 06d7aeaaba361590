#pragma once
// The real "crane" capture (../shared/data/real/vlasic-crane, SOURCES.md there): 8 cameras,
// 1600 x 1200 real silhouettes, imported the way a user would (hullpose_import: projection
// matrices, metres, y up, floor y = 0), for the fusion core's tests and benchmarks on real hulls.
#include <opencv2/core/mat.hpp>
#include <vector>

#include "hullpose/common/rig.hpp"

namespace hullpose::fusion::testing {

struct CraneFrames {
  Rig rig;
  std::vector<int> frames;                  // source frame numbers (0..119)
  std::vector<std::vector<cv::Mat>> views;  // [frame][camera], CV_8UC1, 255 = person
};

// `count` frames spread evenly over the 120 frames.
CraneFrames load_crane(int count);

}  // namespace hullpose::fusion::testing
