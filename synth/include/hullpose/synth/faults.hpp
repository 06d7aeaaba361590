#pragma once
// Fault injection for synthetic datasets. Every draw is a pure function of (seed, camera,
// frame, kind), so results do not depend on thread scheduling or on which frames are rendered.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "hullpose/common/rig.hpp"

namespace hullpose::synth {

struct FaultSpec {
  double salt = 0;       // probability that a background pixel turns foreground
  double pepper = 0;     // probability that a silhouette pixel turns background
  double blobs = 0;      // mean number of spurious foreground blobs per mask (Poisson)
  double holes = 0;      // mean number of holes punched into the silhouette per mask
  double blob_px = 10;   // mean blob and hole radius, pixels
  double calib_px = 0;   // sigma of the principal-point error of the written rig, pixels
  double calib_deg = 0;  // sigma of the rotation error of the written rig, degrees
  double jitter_ms = 0;  // sigma of each camera's trigger-time error, per frame
  double drop = 0;       // probability that a camera's frame is missing
  int dark_camera = -1;  // this camera goes dark (black frames, empty masks) ...
  int dark_from = 0;     // ... from this frame on

  bool any() const;
  bool silhouette_noise() const { return salt > 0 || pepper > 0 || blobs > 0 || holes > 0; }
  // "salt=0.001,pepper=0.001,blobs=1,holes=1,blob_px=10,calib_px=2,calib_deg=0.5,
  //  jitter_ms=4,drop=0.02,dark=3@120" (any subset; "" or "none" = no faults).
  static FaultSpec parse(std::string_view spec);
  // The canonical form parse() reads back; "" when there are no faults.
  std::string describe() const;
};

// Deterministic 64-bit seed for one (camera, frame, kind) draw.
uint64_t draw_seed(uint64_t seed, int camera, int frame, int kind);

// The rig an estimator would be given after an imperfect calibration: every camera's
// principal point and rotation perturbed (Gaussian, per camera, seeded). The true rig renders.
Rig perturb_calibration(const Rig& rig, const FaultSpec& spec, uint64_t seed);
// Trigger-time error of `camera` at `frame`, seconds.
double trigger_offset_s(const FaultSpec& spec, uint64_t seed, int camera, int frame);
bool frame_dropped(const FaultSpec& spec, uint64_t seed, int camera, int frame);
inline bool camera_dark(const FaultSpec& spec, int camera, int frame) {
  return camera == spec.dark_camera && frame >= spec.dark_from;
}
// Salt/pepper, blobs and holes on an 8-bit mask (255 = person), in place.
void corrupt_silhouette(cv::Mat& mask, const FaultSpec& spec, uint64_t seed, int camera, int frame);

}  // namespace hullpose::synth
