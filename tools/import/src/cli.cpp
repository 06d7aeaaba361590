#include "hullpose/import/cli.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <iomanip>
#include <string_view>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/import/recording_import.hpp"
#include "hullpose/import/rig_import.hpp"
#include "hullpose/import/silhouette_import.hpp"

namespace hullpose::import {
namespace {

constexpr const char* kUsage =
    "usage: hullpose-import rig (--projections PATTERN | --opencv PATTERN) --size WxH --units "
    "m|cm|mm|in\n"
    "                           --up AXIS --floor F --out RIG.yaml [--cameras 1,2,...] [--rig-id "
    "ID]\n"
    "                           [--volume-min-mm X,Y,Z --volume-max-mm X,Y,Z | --volume-size-mm "
    "X,Y,Z |\n"
    "                            --max-height-mm H]\n"
    "       hullpose-import silhouettes --rig RIG.yaml --pattern PATTERN --out DIR [--first F] "
    "[--frames N]\n"
    "                           [--fps 30] [--threshold 127] [--motion NAME]\n"
    "PATTERN: {N} is the camera number (= our camera id), {F} the frame number, zero-padded to as "
    "many\n"
    "digits as letters: 'calibration/camera{N}.P', 'cam{N}/config.xml', "
    "'silhouettes/camera{N}_{FFFF}.png'.\n"
    "rig: --projections reads 3x4 projection matrices (RQ split; skew reported and dropped), "
    "--opencv\n"
    "OpenCV FileStorage files (CameraMatrix, DistortionCoeffs, Rotation, Translation: world -> "
    "camera).\n"
    "The source world: --units of its coordinates, --up its up axis (y, -z, ...), --floor the "
    "floor's\n"
    "coordinate along that axis. Ours: mm, z up, floor z = 0. Capture volume: the box every "
    "camera\n"
    "sees (from the floor, at most --max-height-mm high), or a box of --volume-size-mm on the "
    "floor\n"
    "centred where the cameras' optical axes meet, or the box given.\n"
    "silhouettes: re-encodes each camera's images into the dataset layout (docs/conventions.md);\n"
    "grey above --threshold is the person. Then: hullpose-fusion-host --replay DIR --out est.csv\n"
    "recording: runs each camera node config (file source: video or images, its background, method "
    "and\n"
    "clean-up) in-process and writes every frame's colour image and silhouette into the dataset "
    "layout.\n";

std::vector<double> parse_list(const std::string& name, const std::string& text) {
  std::vector<double> v;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    v.push_back(cli::parse_double(name, std::string_view(text).substr(start, comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return v;
}

Eigen::Vector3d parse_point(const std::string& name, const std::string& text) {
  const std::vector<double> v = parse_list(name, text);
  HULLPOSE_THROW_UNLESS(v.size() == 3, name << ": expected X,Y,Z, got '" << text << "'");
  return {v[0], v[1], v[2]};
}

int rig_command(int argc, const char* const* argv, std::ostream& out) {
  RigImportOptions o;
  std::string projections, opencv, size, units, up, min_mm, max_mm, size_mm, rig_out, cameras;
  double floor = std::nan("");
  cli::CommandLine line(kUsage);
  line.option("--projections", projections)
      .option("--opencv", opencv)
      .option("--size", size)
      .option("--units", units)
      .option("--up", up)
      .option("--floor", floor)
      .option("--out", rig_out)
      .option("--cameras", cameras)
      .option("--rig-id", o.rig_id)
      .option("--volume-min-mm", min_mm)
      .option("--volume-max-mm", max_mm)
      .option("--volume-size-mm", size_mm)
      .option("--max-height-mm", o.max_height_mm);
  if (!line.parse(argc, argv, out)) return 0;
  HULLPOSE_THROW_UNLESS(projections.empty() != opencv.empty(),
                        "give one of --projections or --opencv (see --help)");
  HULLPOSE_THROW_UNLESS(!rig_out.empty(), "--out RIG.yaml is needed");
  // The source world is never guessed: a wrong guess gives a rig that looks right and is not.
  HULLPOSE_THROW_UNLESS(
      !units.empty() && !up.empty() && !std::isnan(floor),
      "--units, --up and --floor describe the source world and are all needed (see --help)");
  o.kind = projections.empty() ? SourceKind::kOpenCv : SourceKind::kProjection;
  o.pattern = projections.empty() ? opencv : projections;
  o.world.mm_per_unit = parse_units(units);
  o.world.up = parse_axis(up);
  o.world.floor = floor;
  const size_t x = size.find('x');
  HULLPOSE_THROW_UNLESS(x != std::string::npos,
                        "--size: expected WxH, e.g. 1600x1200, got '" << size << "'");
  o.width = static_cast<int>(cli::parse_integer("--size", size.substr(0, x)));
  o.height = static_cast<int>(cli::parse_integer("--size", size.substr(x + 1)));
  if (!cameras.empty())
    for (double n : parse_list("--cameras", cameras)) o.cameras.push_back(static_cast<int>(n));
  HULLPOSE_THROW_UNLESS(min_mm.empty() == max_mm.empty(),
                        "--volume-min-mm and --volume-max-mm go together");
  if (!size_mm.empty()) {
    o.volume_size_mm = parse_point("--volume-size-mm", size_mm);
    HULLPOSE_THROW_UNLESS((o.volume_size_mm->array() > 0).all(),
                          "--volume-size-mm: every side must be positive");
  }
  if (!min_mm.empty())
    o.volume = CaptureVolume{parse_point("--volume-min-mm", min_mm),
                             parse_point("--volume-max-mm", max_mm)};

  const RigImport r = import_rig(o);
  save_rig(r.rig, rig_out);
  out << std::fixed;
  for (const ImportedCamera& ic : r.cameras) {
    const CameraModel& c = ic.camera;
    const Eigen::Vector3d centre = c.centre();
    // Viewing direction in our world: the camera's z axis.
    const Eigen::Vector3d view = c.R.row(2).transpose();
    out << "camera " << c.id << " (" << ic.source.string() << "): f " << std::setprecision(1)
        << c.fx << "," << c.fy << " c " << c.cx << "," << c.cy << " centre [" << centre.x() << ", "
        << centre.y() << ", " << centre.z() << "] mm, looking " << std::setprecision(1)
        << std::asin(std::clamp(-view.z(), -1.0, 1.0)) * 180 / M_PI << " deg down";
    if (o.kind == SourceKind::kProjection)
      out << ", skew " << std::setprecision(3) << ic.skew_px << " px (dropped: up to "
          << ic.skew_shift_px << " px)";
    if (ic.rotation_repair > 0)
      out << ", rotation re-orthonormalised (deviation " << std::scientific << ic.rotation_repair
          << std::fixed << ")";
    out << "\n";
  }
  out << std::setprecision(0) << "capture volume [" << r.rig.volume.min_mm.transpose() << "] .. ["
      << r.rig.volume.max_mm.transpose() << "] mm\nwrote " << rig_out << "\n";
  return 0;
}

int silhouettes_command(int argc, const char* const* argv, std::ostream& out) {
  SilhouetteImportOptions o;
  std::string rig, dir;
  cli::CommandLine line(kUsage);
  line.option("--rig", rig)
      .option("--pattern", o.pattern)
      .option("--out", dir)
      .option("--first", o.first)
      .option("--frames", o.frames)
      .option("--fps", o.fps)
      .option("--threshold", o.threshold)
      .option("--motion", o.motion);
  if (!line.parse(argc, argv, out)) return 0;
  HULLPOSE_THROW_UNLESS(!rig.empty() && !o.pattern.empty() && !dir.empty(),
                        "--rig, --pattern and --out are all needed (see --help)");
  o.rig = rig;
  o.out = dir;
  const SilhouetteImport s = import_silhouettes(o);
  out << "wrote " << dir << ": " << s.frames << " frames, " << s.masks << " masks, " << s.missing
      << " missing, " << s.unreadable << " unreadable (cameras without a mask in those frames)\n";
  return 0;
}

int recording_command(int argc, const char* const* argv, std::ostream& out) {
  RecordingImportOptions o;
  std::string dir;
  bool no_rgb = false;
  cli::CommandLine line(kUsage);
  line.option("--node-config", [&](const std::string& v) { o.node_configs.emplace_back(v); })
      .option("--out", dir)
      .option("--frames", o.frames)
      .option("--fps", o.fps)
      .flag("--no-rgb", no_rgb);
  if (!line.parse(argc, argv, out)) return 0;
  HULLPOSE_THROW_UNLESS(!dir.empty(), "--out DIR is needed");
  o.out = dir;
  o.rgb = !no_rgb;
  const RecordingImport r = import_recordings(o);
  out << "wrote " << dir << ": " << r.frames << " frames, " << r.masks << " masks, " << r.corrupt
      << " corrupt frames (those cameras missing there)\n";
  return 0;
}

}  // namespace

int run_cli(int argc, const char* const* argv, std::ostream& out) {
  const std::string_view command = argc > 1 ? argv[1] : "";
  if (command == "rig") return rig_command(argc - 1, argv + 1, out);
  if (command == "silhouettes") return silhouettes_command(argc - 1, argv + 1, out);
  if (command == "recording") return recording_command(argc - 1, argv + 1, out);
  if (command == "-h" || command == "--help") {
    out << kUsage;
    return 0;
  }
  HULLPOSE_THROW("expected 'rig', 'silhouettes' or 'recording' first, got '" << command
                                                                             << "' (see --help)");
}

}  // namespace hullpose::import
