#include "hullpose/calibrate/options.hpp"

#include <charconv>
#include <cstdio>

#include "hullpose/common/check.hpp"

namespace hullpose::calibrate {
namespace {

double to_double(const std::string& flag, const std::string& value) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  HULLPOSE_THROW_UNLESS(used == value.size() && !value.empty(),
                        flag << ": '" << value << "' is not a number");
  return v;
}

int to_int(const std::string& flag, const std::string& value) {
  int v = 0;
  const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  HULLPOSE_THROW_UNLESS(ec == std::errc() && ptr == value.data() + value.size() && !value.empty(),
                        flag << ": '" << value << "' is not an integer");
  return v;
}

}  // namespace

std::string usage() {
  return "usage: hullpose-calibrate (--images DIR | --node-config FILE...) --board COLSxROWS "
         "--square-mm S\n"
         "                          --out RIG.yaml [options]\n"
         "  DIR holds cam<ID>/<instant>.png; images with the same <instant> name were taken "
         "together.\n"
         "  --node-config FILE       live: a camera node's config (its camera id and frame "
         "source:\n"
         "                           libcamera, v4l2, file, synthetic); repeat once per camera. "
         "Instants\n"
         "                           are named live00000, live00001, ... (--floor-view live00042)\n"
         "  --frames N               live: stop after N instants (default: when a source ends)\n"
         "  --stride N               live: one instant every N frames (default 1)\n"
         "  --timeout-ms T           live: a camera silent this long is an error (default 2000)\n"
         "  --board COLSxROWS        inner corners, one side even and one odd (e.g. 9x6)\n"
         "  --square-mm S            square size in mm\n"
         "  --floor-view NAME        instant with the board lying printed face up on the floor\n"
         "                           (default: floor). Repeat it for the board laid at several\n"
         "                           spots on the floor: the first sets the origin and x axis, "
         "all\n"
         "                           of them the floor plane (more accurate than one board)\n"
         "  --board-thickness-mm T   height of the floor board's face above the floor (default 0)\n"
         "  --rig-id ID              rig id written to the rig file (default: calibrated)\n"
         "  --min-views N            board views a camera needs for its intrinsics (default 8)\n"
         "  --fix-intrinsics         keep the per-camera intrinsics in the bundle adjustment\n"
         "  --intrinsics RIG.yaml    known intrinsics (by camera id, e.g. hullpose-import rig): "
         "only the\n"
         "                           board poses and the extrinsics are estimated; one view per "
         "camera\n"
         "                           (the floor board) is enough\n"

         "  --no-k3                  do not estimate the k3 distortion coefficient\n"
         "  --volume-min-cameras N   capture volume: points seen by N cameras (default: all)\n"
         "  --max-rms-px E           refuse a rig whose RMS reprojection error exceeds E (default "
         "2)\n"
         "  --report FILE            also write the report to FILE\n"
         "  --compare RIG.yaml       how the result agrees with another calibration of the rig\n"
         "                           (per camera centre mm, orientation deg, after aligning "
         "frames)\n"
         "  --quiet                  no per-image feedback\n";
}

CommandLine parse_command_line(int argc, const char* const* argv) {
  CommandLine cli;
  bool have_board = false, have_square = false, have_floor = false;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    auto value = [&]() -> std::string {
      HULLPOSE_THROW_UNLESS(i + 1 < argc, flag << ": missing value");
      return argv[++i];
    };
    if (flag == "--help" || flag == "-h") {
      cli.help = true;
      return cli;
    } else if (flag == "--images") {
      cli.images = value();
    } else if (flag == "--node-config") {
      cli.node_configs.emplace_back(value());
    } else if (flag == "--frames") {
      cli.live.max_instants = to_int(flag, value());
    } else if (flag == "--stride") {
      cli.live.stride = to_int(flag, value());
    } else if (flag == "--timeout-ms") {
      cli.live.timeout_ms = to_int(flag, value());
    } else if (flag == "--out") {
      cli.out = value();
    } else if (flag == "--compare") {
      cli.compare = value();
    } else if (flag == "--report") {
      cli.report = value();
    } else if (flag == "--board") {
      const std::string v = value();
      const auto x = v.find('x');
      HULLPOSE_THROW_UNLESS(x != std::string::npos,
                            "--board: '" << v << "' must be COLSxROWS, e.g. 9x6");
      cli.options.board.cols = to_int("--board", v.substr(0, x));
      cli.options.board.rows = to_int("--board", v.substr(x + 1));
      have_board = true;
    } else if (flag == "--square-mm") {
      cli.options.board.square_mm = to_double(flag, value());
      have_square = true;
    } else if (flag == "--floor-view") {
      if (!have_floor) cli.options.floor_views.clear();  // the first one replaces the default
      cli.options.floor_views.push_back(value());
      have_floor = true;
    } else if (flag == "--board-thickness-mm") {
      cli.options.board_thickness_mm = to_double(flag, value());
    } else if (flag == "--rig-id") {
      cli.options.rig_id = value();
    } else if (flag == "--min-views") {
      cli.options.intrinsics.min_views = to_int(flag, value());
    } else if (flag == "--intrinsics") {
      for (const CameraModel& c : load_rig(value()).cameras) cli.options.known_intrinsics[c.id] = c;
    } else if (flag == "--fix-intrinsics") {
      cli.options.refine_intrinsics = false;
    } else if (flag == "--no-k3") {
      cli.options.intrinsics.estimate_k3 = false;
    } else if (flag == "--volume-min-cameras") {
      cli.options.volume_min_cameras = to_int(flag, value());
    } else if (flag == "--max-rms-px") {
      cli.options.max_rms_px = to_double(flag, value());
    } else if (flag == "--quiet") {
      cli.quiet = true;
    } else {
      HULLPOSE_THROW("unknown argument '" << flag << "' (see --help)");
    }
  }
  HULLPOSE_THROW_UNLESS(
      cli.images.empty() != cli.node_configs.empty(),
      "give either --images DIR or --node-config FILE (one per camera), not both (see --help)");
  HULLPOSE_THROW_UNLESS(!cli.out.empty(), "--out RIG.yaml is required (see --help)");
  HULLPOSE_THROW_UNLESS(have_board && have_square,
                        "--board and --square-mm are required (see --help)");
  cli.options.board.validate();
  return cli;
}

}  // namespace hullpose::calibrate
