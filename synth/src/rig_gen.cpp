#include "hullpose/synth/rig_gen.hpp"

#include <Eigen/Geometry>
#include <charconv>
#include <string_view>

#include "hullpose/common/check.hpp"

namespace hullpose::synth {

void look_at(CameraModel& camera, const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - centre).normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-9) x = Eigen::Vector3d::UnitX();  // looking straight down or up
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  camera.R.row(0) = x.transpose();
  camera.R.row(1) = y.transpose();
  camera.R.row(2) = z.transpose();
  camera.t = -camera.R * centre;
}

Rig make_ring_rig(const RingRigSpec& s) {
  HULLPOSE_THROW_UNLESS(s.ring_cameras >= 1 && s.ring_cameras <= 63,
                        "ring cameras " << s.ring_cameras << " must be 1..63");
  HULLPOSE_THROW_UNLESS(s.volume_x_mm > 0 && s.volume_y_mm > 0 && s.volume_z_mm > 0,
                        "capture volume must have a positive size");
  HULLPOSE_THROW_UNLESS(
      s.radius_mm > 0.5 * std::hypot(s.volume_x_mm, s.volume_y_mm),
      "ring radius " << s.radius_mm << " mm puts the cameras inside the capture volume");
  HULLPOSE_THROW_UNLESS(
      s.vfov_deg > 1 && s.vfov_deg < 170 && s.ceiling_vfov_deg > 1 && s.ceiling_vfov_deg < 170,
      "field of view must be in (1, 170) degrees");
  Rig rig;
  rig.rig_id = s.rig_id;
  rig.volume.min_mm = Eigen::Vector3d(-s.volume_x_mm / 2, -s.volume_y_mm / 2, 0);
  rig.volume.max_mm = Eigen::Vector3d(s.volume_x_mm / 2, s.volume_y_mm / 2, s.volume_z_mm);
  auto intrinsics = [&](CameraModel& c, double vfov_deg) {
    c.width = s.width;
    c.height = s.height;
    c.fy = 0.5 * s.height / std::tan(0.5 * vfov_deg * M_PI / 180);
    c.fx = c.fy;
    c.cx = 0.5 * s.width - 0.5;  // the image centre, in OpenCV's pixel-centre convention
    c.cy = 0.5 * s.height - 0.5;
    c.dist = {s.k1, 0, 0, 0, 0};
  };
  const Eigen::Vector3d aim(0, 0, 0.5 * s.volume_z_mm);
  for (int i = 0; i < s.ring_cameras; ++i) {
    CameraModel c;
    c.id = i;
    c.name = "ring" + std::to_string(i);
    intrinsics(c, s.vfov_deg);
    const double az = (s.azimuth0_deg + 360.0 * i / s.ring_cameras) * M_PI / 180;
    const Eigen::Vector3d centre(s.radius_mm * std::cos(az), s.radius_mm * std::sin(az),
                                 s.height_mm);
    Eigen::Vector3d target = aim;
    if (!std::isnan(s.tilt_deg))
      target = Eigen::Vector3d(0, 0, s.height_mm - s.radius_mm * std::tan(s.tilt_deg * M_PI / 180));
    look_at(c, centre, target);
    rig.cameras.push_back(c);
  }
  if (s.ceiling) {
    CameraModel c;
    c.id = s.ring_cameras;
    c.name = "ceiling";
    intrinsics(c, s.ceiling_vfov_deg);
    HULLPOSE_THROW_UNLESS(
        s.ceiling_height_mm > s.volume_z_mm + 300,
        "ceiling camera at " << s.ceiling_height_mm << " mm is not above the capture volume");
    look_at(c, Eigen::Vector3d(0, 0, s.ceiling_height_mm), Eigen::Vector3d(0, 0, 0));
    rig.cameras.push_back(c);
  }
  rig.validate();
  return rig;
}

Rig rig_from_name_or_file(const std::string& spec) {
  if (spec == "thesis8") return make_ring_rig({});
  if (spec.rfind("ring:", 0) != 0) return load_rig(spec);
  RingRigSpec r;
  r.rig_id = "ring";
  std::string_view rest = std::string_view(spec).substr(5);
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    const size_t eq = item.find('=');
    HULLPOSE_THROW_UNLESS(eq != std::string_view::npos,
                          "rig '" << spec << "': '" << item << "' is not key=value");
    const std::string key(item.substr(0, eq)), text(item.substr(eq + 1));
    double v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    HULLPOSE_THROW_UNLESS(ec == std::errc() && end == text.data() + text.size() && std::isfinite(v),
                          "rig '" << spec << "': " << key << "='" << text << "' is not a number");
    if (key == "cameras")
      r.ring_cameras = static_cast<int>(v);
    else if (key == "radius")
      r.radius_mm = v;
    else if (key == "height")
      r.height_mm = v;
    else if (key == "tilt")
      r.tilt_deg = v;
    else if (key == "ceiling")
      r.ceiling = v != 0;
    else if (key == "vfov")
      r.vfov_deg = v;
    else if (key == "k1")
      r.k1 = v;
    else if (key == "width")
      r.width = static_cast<int>(v);
    else if (key == "rows")
      r.height = static_cast<int>(v);
    else
      HULLPOSE_THROW(
          "rig '" << spec << "': unknown key '" << key
                  << "' (cameras, radius, height, tilt, ceiling, vfov, k1, width, rows)");
  }
  return make_ring_rig(r);
}

}  // namespace hullpose::synth
