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

// The capture volume of the imported rig.
enum class CraneVolume {
  kImport,  // what `hullpose-import rig` gives without volume options: the box every camera sees
            // (3.65 m across; 28.5 mm voxels at 128³)
  kThesis,  // the thesis rig's 2.4 x 2.4 x 2.2 m where the optical axes meet (18.75 mm voxels)
};

// `count` frames spread evenly over the 120 frames.
CraneFrames load_crane(int count, CraneVolume volume = CraneVolume::kThesis);

}  // namespace hullpose::fusion::testing
