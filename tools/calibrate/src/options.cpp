#include "hullpose/calibrate/options.hpp"

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/yaml.hpp"

namespace hullpose::calibrate {

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
         "  --exhaustive-search      small images: also search exhaustively for boards of a few\n"
         "                           pixels a square (seconds per image without a board)\n"
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
         "  --corners FILE           board corners marked by hand, for boards no detector finds "
         "or\n"
         "                           symmetric ones (both sides even): per camera and view, the\n"
         "                           pixels of inner corners (0,0), (COLS-1,0), (COLS-1,ROWS-1),\n"
         "                           (0,ROWS-1); a symmetric board's unmarked images are "
         "skipped\n"
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

namespace {

// marks:
//   - {camera: 1, view: floor, corners: [x0, y0, x1, y1, x2, y2, x3, y3]}
std::map<std::pair<int, std::string>, MarkedCorners> read_marks(const std::string& file) {
  const yaml::Document doc = yaml::Document::load(file);
  std::map<std::pair<int, std::string>, MarkedCorners> out;
  for (const yaml::Node& m : doc.root().need("marks").items()) {
    const auto key =
        std::make_pair(static_cast<int>(m.need("camera").integer(0, 63)), m.need("view").string());
    const std::vector<double> xy = m.need("corners").reals(8);
    MarkedCorners corners;
    for (size_t k = 0; k < 4; ++k)
      corners[k] = {static_cast<float>(xy[2 * k]), static_cast<float>(xy[2 * k + 1])};
    HULLPOSE_THROW_UNLESS(out.emplace(key, corners).second, m.where() << ": camera " << key.first
                                                                      << ", view " << key.second
                                                                      << " is marked twice");
  }
  doc.check_all_read();
  HULLPOSE_THROW_UNLESS(!out.empty(), file << ": marks: no view is marked");
  return out;
}

}  // namespace

std::optional<CommandLine> parse_command_line(int argc, const char* const* argv) {
  CommandLine cli;
  bool have_board = false, have_square = false, have_floor = false;
  std::string images, out, report, compare;
  cli::CommandLine line(usage());
  line.option("--images", images)
      .option("--node-config", [&](const std::string& v) { cli.node_configs.emplace_back(v); })
      .option("--frames", cli.live.max_instants)
      .option("--stride", cli.live.stride)
      .option("--timeout-ms", cli.live.timeout_ms)
      .option("--out", out)
      .option("--report", report)
      .option("--compare", compare)
      .option("--intrinsics",
              [&](const std::string& v) {
                for (const CameraModel& c : load_rig(v).cameras)
                  cli.options.known_intrinsics[c.id] = c;
              })
      .option("--board",
              [&](const std::string& v) {
                const auto x = v.find('x');
                HULLPOSE_THROW_UNLESS(x != std::string::npos,
                                      "--board: '" << v << "' must be COLSxROWS, e.g. 9x6");
                cli.options.board.cols =
                    static_cast<int>(cli::parse_integer("--board", v.substr(0, x)));
                cli.options.board.rows =
                    static_cast<int>(cli::parse_integer("--board", v.substr(x + 1)));
                have_board = true;
              })
      .option("--square-mm",
              [&](const std::string& v) {
                cli.options.board.square_mm = cli::parse_double("--square-mm", v);
                have_square = true;
              })
      .option("--floor-view",
              [&](const std::string& v) {
                if (!have_floor)
                  cli.options.floor_views.clear();  // the first one replaces the default
                cli.options.floor_views.push_back(v);
                have_floor = true;
              })
      .option("--board-thickness-mm", cli.options.board_thickness_mm)
      .option("--rig-id", cli.options.rig_id)
      .option("--min-views", cli.options.intrinsics.min_views)
      .flag("--fix-intrinsics", [&] { cli.options.refine_intrinsics = false; })
      .flag("--exhaustive-search", [&] { cli.options.board.exhaustive_search = true; })
      .option("--corners",
              [&](const std::string& v) {
                cli.options.marked_corners = read_marks(v);
                cli.options.board.corners_marked = true;
              })
      .flag("--no-k3", [&] { cli.options.intrinsics.estimate_k3 = false; })
      .option("--volume-min-cameras", cli.options.volume_min_cameras)
      .option("--max-rms-px", cli.options.max_rms_px)
      .flag("--quiet", cli.quiet);
  if (!line.parse(argc, argv)) return std::nullopt;
  cli.images = images;
  cli.out = out;
  cli.report = report;
  cli.compare = compare;
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
