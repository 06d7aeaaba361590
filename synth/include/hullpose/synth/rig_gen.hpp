#pragma once
// Virtual rigs: N cameras on a ring around the capture volume, aimed at its centre, plus an
// optional ceiling camera looking straight down (the thesis' setup is 7 + 1 at 800 x 600).
#include <cmath>
#include <limits>
#include <string>

#include "hullpose/common/rig.hpp"

namespace hullpose::synth {

struct RingRigSpec {
  std::string rig_id = "thesis8";
  int ring_cameras = 7;
  double radius_mm = 5000;  // ring radius, horizontal distance from the volume centre
  double height_mm = 2600;  // camera height above the floor
  double tilt_deg =
      std::numeric_limits<double>::quiet_NaN();  // downward pitch; NaN = aim at the volume centre
  double azimuth0_deg = 0;  // azimuth of camera 0 (others follow anticlockwise)
  bool ceiling = true;      // add camera id ring_cameras at the ceiling, looking down
  double ceiling_height_mm = 5500;
  int width = 800, height = 600;
  double vfov_deg = 58;  // ring cameras' vertical field of view
  double ceiling_vfov_deg = 58;
  double k1 = 0;  // radial distortion given to every camera (0 = ideal lenses)
  // The capture volume: a box on the floor around the centre that holds the subject (CMU 55_01
  // "dance, whirl" spans 2.4 m x 3.1 m).
  double volume_x_mm = 3400, volume_y_mm = 3400, volume_z_mm = 2200;
};

// Throws hullpose::Error on a spec that gives no valid rig (e.g. a camera inside the volume).
Rig make_ring_rig(const RingRigSpec& spec);

// "thesis8" = make_ring_rig({}); "ring:cameras=12,radius=4500,height=2000,tilt=15,ceiling=0,
// vfov=50,k1=-0.1,width=1280,rows=720" (any subset, the rest as thesis8) a custom ring;
// anything else is a rig file path.
Rig rig_from_name_or_file(const std::string& spec);

// Camera extrinsics looking from `centre` at `target` (world z up, camera y down).
void look_at(CameraModel& camera, const Eigen::Vector3d& centre, const Eigen::Vector3d& target);

}  // namespace hullpose::synth
