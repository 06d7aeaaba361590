#pragma once
// How two calibrations of one rig agree (`hullpose-calibrate --compare OTHER.yaml`). Their world
// frames may differ (another tool's origin and axes): the rigid motion that best maps this rig's
// camera centres onto the other's (least squares, no scale; Umeyama) is removed first, so what is
// left per camera is the calibrations' disagreement, not the choice of frame.
#include <iosfwd>
#include <vector>

#include "hullpose/common/rig.hpp"

namespace hullpose::calibrate {

struct CameraDifference {
  int id = 0;
  double centre_mm = 0;        // |aligned centre - other centre|
  double orientation_deg = 0;  // angle of the aligned rotation times the other's inverse
  double focal_pct = 0;        // (fx - fx_other) / fx_other, mean of x and y
  double principal_px = 0;     // |(cx, cy) - (cx, cy)_other|
};

struct RigDifference {
  std::vector<CameraDifference> cameras;  // cameras in both rigs, by id
  double frame_rotation_deg = 0;          // the alignment: how the two world frames differ
  double frame_translation_mm = 0;
};

// Needs 3 or more cameras in common (2 leave the turn about their baseline free); throws
// hullpose::Error otherwise.
RigDifference compare_rigs(const Rig& rig, const Rig& other);
void print_difference(std::ostream& out, const RigDifference& d);

}  // namespace hullpose::calibrate
