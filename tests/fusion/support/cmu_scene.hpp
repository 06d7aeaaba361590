#pragma once
// CMU 55_01 ("dance, whirl", the thesis' dance-whirl sequence) rendered by hullpose_synth with
// the thesis rig (7 ring cameras + 1 ceiling camera, 800 x 600): exact silhouettes of selected
// frames, for the fusion core's tests and benchmarks.
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "hullpose/common/rig.hpp"

namespace hullpose::fusion::testing {

struct CmuFrames {
  Rig rig;                                  // hullpose_synth's "thesis8"
  std::vector<int> frames;                  // frame indices at 30 fps
  std::vector<std::vector<cv::Mat>> views;  // [frame][camera], CV_8UC1, 255 = person
};

// `count` frames spread evenly over the clip (../shared/data/mocap/55_01.bvh, 30 fps), seen by
// `rig` (synth::rig_from_name_or_file: "thesis8", "ring:cameras=19,width=1024,rows=768", ...).
CmuFrames render_cmu_55_01(int count, const std::string& rig = "thesis8");

}  // namespace hullpose::fusion::testing
