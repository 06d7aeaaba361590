#include "hullpose/calibrate/rig_calibrator.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <opencv2/core/utility.hpp>
#include <ostream>
#include <sstream>

#include "hullpose/calibrate/bundle_adjust.hpp"
#include "hullpose/calibrate/extrinsics.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose::calibrate {

HULLPOSE_LOG_CATEGORY(Calibrate, "calibrate")

namespace {

// A floor view's board, chained from the cameras, may sit this far off the first floor board's
// plane: chaining errors are millimetres and fractions of a degree, a board on a table or
// propped against a wall is far beyond.
constexpr double kMaxFloorTiltDeg = 10;
constexpr double kMaxFloorHeightMm = 50;

// A camera's error in the rig may exceed its error alone by this factor plus slack.
constexpr double kMaxRigToIntrinsicRms = 1.5;
constexpr double kRigRmsSlackPx = 0.1;

std::string camera_list(const std::vector<int>& ids) {
  std::ostringstream s;
  for (size_t i = 0; i < ids.size(); ++i) s << (i ? ", " : "") << ids[i];
  return s.str();
}

}  // namespace

RigCalibrator::RigCalibrator(CalibrationOptions options, std::ostream* feedback)
    : options_(std::move(options)), feedback_(feedback) {
  options_.intrinsics.live_estimates = feedback_ != nullptr;
  options_.board.validate();
  HULLPOSE_THROW_UNLESS(!options_.floor_views.empty(),
                        "name at least one floor view (the board lying on the floor)");
  for (size_t i = 0; i < options_.floor_views.size(); ++i) {
    const std::string& name = options_.floor_views[i];
    HULLPOSE_THROW_UNLESS(!name.empty(), "a floor view name must not be empty");
    HULLPOSE_THROW_UNLESS(std::find(options_.floor_views.begin() + static_cast<long>(i) + 1,
                                    options_.floor_views.end(), name) == options_.floor_views.end(),
                          "floor view '" << name << "' is named twice");
  }
}

int RigCalibrator::view_index(const std::string& view) {
  const auto [it, inserted] = view_index_.emplace(view, static_cast<int>(views_.size()));
  if (inserted) views_.push_back(view);
  return it->second;
}

void RigCalibrator::add(const CaptureInstant& instant) {
  std::vector<std::vector<cv::Point2f>> corners(instant.images.size());
  std::vector<size_t> unmarked;
  for (size_t i = 0; i < instant.images.size(); ++i) {
    const auto key = std::make_pair(instant.images[i].camera_id, instant.name);
    const auto mark = options_.marked_corners.find(key);
    if (mark == options_.marked_corners.end()) {
      unmarked.push_back(i);
      continue;
    }
    try {
      corners[i] = corners_from_marks(instant.images[i].image, options_.board, mark->second);
    } catch (const Error& e) {
      HULLPOSE_THROW("camera " << key.first << ", view " << key.second << ": " << e.what());
    }
    marks_used_.insert(key);
  }
  // Detection dominates the run time and the images are independent: one task per image.
  cv::parallel_for_(cv::Range(0, static_cast<int>(unmarked.size())), [&](const cv::Range& range) {
    for (int k = range.start; k < range.end; ++k) {
      const size_t i = unmarked[static_cast<size_t>(k)];
      corners[i] = detect_board(instant.images[i].image, options_.board);
    }
  });
  for (size_t i = 0; i < instant.images.size(); ++i)
    add_detection(instant.name, instant.images[i].camera_id, instant.images[i].image.size(),
                  std::move(corners[i]));
}

void RigCalibrator::add_all(ViewProvider& provider) {
  CaptureInstant instant;
  while (provider.next(instant)) add(instant);
}

void RigCalibrator::add_detection(const std::string& view, int camera_id, cv::Size image_size,
                                  std::vector<cv::Point2f> corners) {
  HULLPOSE_THROW_UNLESS(camera_id >= 0 && camera_id < 64,
                        "camera id " << camera_id << " must be in 0..63");
  view_index(view);
  auto it = cameras_.find(camera_id);
  if (it == cameras_.end())
    it = cameras_
             .emplace(camera_id,
                      IntrinsicsCalibrator(camera_id, options_.board, options_.intrinsics))
             .first;
  const ViewFeedback fb = it->second.add_view(view, image_size, std::move(corners));
  if (!feedback_) return;
  std::ostream& out = *feedback_;
  out << "cam" << fb.camera_id << " " << fb.view << ": ";
  if (!fb.found) {
    out << "no board: " << board_search_summary(options_.board, image_size);
  } else {
    out << "board found";
    if (fb.view_rms_px)
      out << ", error " << std::fixed << std::setprecision(2) << *fb.view_rms_px << " px"
          << (fb.outlier ? " (outlier, will be rejected)" : "");
  }
  out << "; " << fb.views_kept << " views, coverage " << std::fixed << std::setprecision(0)
      << 100 * fb.coverage << "%\n";
  out.flush();
}

namespace {

// solve()'s steps, in order; each hands the next what it needs.

// 1. Intrinsics, every camera on its own (or only its board poses where they are known); every
// camera that fails is reported at once.
std::vector<IntrinsicsResult> calibrate_intrinsics(
    const std::map<int, IntrinsicsCalibrator>& cameras,
    const std::map<int, CameraModel>& known_intrinsics, std::vector<int>& ids) {
  std::vector<IntrinsicsResult> intrinsics;
  std::string failures;
  for (const auto& [id, calibrator] : cameras) {
    ids.push_back(id);
    try {
      const auto known = known_intrinsics.find(id);
      intrinsics.push_back(known != known_intrinsics.end() ? calibrator.with_known(known->second)
                                                           : calibrator.calibrate());
    } catch (const Error& e) {
      failures += std::string(failures.empty() ? "" : "; ") + e.what();
      intrinsics.emplace_back();
    }
  }
  HULLPOSE_THROW_UNLESS(failures.empty(), failures);
  return intrinsics;
}

// Every kept board pose of every camera, with its corners.
struct Observations {
  std::vector<PoseObservation> poses;
  std::vector<const std::vector<cv::Point2f>*> corners;  // parallel to poses
};

Observations board_poses(const std::vector<IntrinsicsResult>& intrinsics,
                         const std::map<std::string, int>& view_index) {
  Observations o;
  for (size_t c = 0; c < intrinsics.size(); ++c) {
    const auto& in = intrinsics[c];
    for (size_t k = 0; k < in.kept.size(); ++k) {
      o.poses.push_back({static_cast<int>(c), view_index.at(in.kept[k].view), in.cam_from_board[k],
                         in.view_rms_px[k]});
      o.corners.push_back(&in.kept[k].corners);
    }
  }
  return o;
}

// 2. The floor views in the order named; the first sets the origin.
std::vector<int> floor_views(const CalibrationOptions& options,
                             const std::map<std::string, int>& view_index,
                             const std::vector<PoseObservation>& poses) {
  std::vector<int> floors;
  for (const auto& name : options.floor_views) {
    const auto it = view_index.find(name);
    HULLPOSE_THROW_UNLESS(it != view_index.end(),
                          "no capture instant named '"
                              << name << "' (a board lying on the floor sets the world frame)");
    HULLPOSE_THROW_UNLESS(
        std::any_of(poses.begin(), poses.end(),
                    [&](const PoseObservation& p) { return p.view == it->second; }),
        "the floor board (instant '" << name << "') was not found (or was rejected) in any camera");
    floors.push_back(it->second);
  }
  return floors;
}

// The camera that saw the first floor board best: the root of the chaining.
int root_camera(const std::vector<PoseObservation>& poses, int floor) {
  int root = -1;
  double root_rms = 0;
  for (const auto& p : poses)
    if (p.view == floor && (root < 0 || p.rms_px < root_rms)) {
      root = p.camera;
      root_rms = p.rms_px;
    }
  return root;
}

// 3. Every camera must be chained to the root through shared views; names the ones that are not.
void check_linked(const Linkage& link, const std::vector<int>& ids, int root) {
  const int n_cams = static_cast<int>(ids.size());
  std::vector<int> unlinked;
  for (int c = 0; c < n_cams; ++c)
    if (!link.linked[static_cast<size_t>(c)]) unlinked.push_back(ids[static_cast<size_t>(c)]);
  if (unlinked.empty()) return;
  std::ostringstream msg;
  msg << (unlinked.size() == 1 ? "camera " : "cameras ") << camera_list(unlinked)
      << " could not be linked to the rig: ";
  for (size_t i = 0; i < unlinked.size(); ++i) {
    const int c = static_cast<int>(std::find(ids.begin(), ids.end(), unlinked[i]) - ids.begin());
    msg << (i ? "; " : "") << "camera " << unlinked[i] << " shares "
        << link.shared_views[static_cast<size_t>(c)] << " board views with other cameras";
  }
  msg << " (linked to the floor board's camera " << ids[static_cast<size_t>(root)] << " are: ";
  std::vector<int> linked;
  for (int c = 0; c < n_cams; ++c)
    if (link.linked[static_cast<size_t>(c)]) linked.push_back(ids[static_cast<size_t>(c)]);
  msg << camera_list(linked) << "); show a board to these cameras together with a linked one";
  HULLPOSE_THROW(msg.str());
}

// 4. The world frame: the first floor board, printed face up, z up, origin under its grid centre.
Eigen::Isometry3d world_from_floor_board(const CalibrationOptions& options) {
  Eigen::Isometry3d w = Eigen::Isometry3d::Identity();
  w.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  w.translation() =
      Eigen::Vector3d(0, 0, options.board_thickness_mm) - w.linear() * options.board.centre_mm();
  return w;
}

// Another floor board starts from its chained pose laid flat on the plane (the bundle adjustment
// keeps it there); one far off the first board's plane was not on the floor.
Eigen::Isometry3d laid_on_floor(const CalibrationOptions& options,
                                const Eigen::Isometry3d& world_from_floor,
                                const Eigen::Isometry3d& chained, const std::string& name) {
  const double tilt_deg =
      std::acos(std::clamp(-chained.linear().col(2).z(), -1.0, 1.0)) * 180.0 / M_PI;
  const double height_mm = chained.translation().z() - options.board_thickness_mm;
  HULLPOSE_THROW_UNLESS(tilt_deg < kMaxFloorTiltDeg && std::abs(height_mm) < kMaxFloorHeightMm,
                        "the board of floor view '"
                            << name << "' is " << std::fixed << std::setprecision(0) << tilt_deg
                            << " degrees and " << height_mm << " mm off the plane of floor view '"
                            << options.floor_views.front()
                            << "': is it lying printed face up on the same floor?");
  const Eigen::Vector3d x = chained.linear().col(0);
  Eigen::Isometry3d flat = Eigen::Isometry3d::Identity();
  flat.linear() = Eigen::AngleAxisd(std::atan2(x.y(), x.x()), Eigen::Vector3d::UnitZ()) *
                  world_from_floor.linear();
  flat.translation() = chained.translation();
  flat.translation().z() = options.board_thickness_mm;
  return flat;
}

// 5. The bundle adjustment's problem: every observation, the first floor board held fixed and
// the others on the floor plane, the cameras and boards where the chaining put them.
BundleProblem bundle_problem(const CalibrationOptions& options,
                             const std::vector<IntrinsicsResult>& intrinsics,
                             const Observations& obs, const std::vector<int>& floors,
                             const Linkage& link, int n_views) {
  const Eigen::Isometry3d world_from_floor = world_from_floor_board(options);
  const int floor = floors.front();
  const Eigen::Isometry3d world_from_root =
      world_from_floor * link.root_from_board[static_cast<size_t>(floor)]->inverse();
  BundleProblem problem;
  for (int i = 0; i < options.board.corner_count(); ++i)
    problem.board_points.push_back(options.board.corner_mm(i));
  for (size_t c = 0; c < intrinsics.size(); ++c) {
    CameraModel cam = intrinsics[c].camera;
    const Eigen::Isometry3d cam_from_world = (world_from_root * link.root_from_cam[c]).inverse();
    cam.R = cam_from_world.linear();
    cam.t = cam_from_world.translation();
    problem.cameras.push_back(cam);
  }
  std::vector<int> board_of_view(static_cast<size_t>(n_views), -1);
  for (int v = 0; v < n_views; ++v) {
    const auto& b = link.root_from_board[static_cast<size_t>(v)];
    if (!b) continue;
    board_of_view[static_cast<size_t>(v)] = static_cast<int>(problem.world_from_board.size());
    const auto floor_rank = std::find(floors.begin(), floors.end(), v) - floors.begin();
    if (v == floor) {
      problem.world_from_board.push_back(world_from_floor);
      problem.board_motion.push_back(BoardMotion::kFixed);
    } else if (floor_rank < static_cast<long>(floors.size())) {
      problem.world_from_board.push_back(
          laid_on_floor(options, world_from_floor, world_from_root * *b,
                        options.floor_views[static_cast<size_t>(floor_rank)]));
      problem.board_motion.push_back(BoardMotion::kOnFloor);
    } else {
      problem.world_from_board.push_back(world_from_root * *b);
      problem.board_motion.push_back(BoardMotion::kFree);
    }
  }
  for (size_t k = 0; k < obs.poses.size(); ++k) {
    BoardObservation o;
    o.camera = obs.poses[k].camera;
    o.board = board_of_view[static_cast<size_t>(obs.poses[k].view)];
    HULLPOSE_ASSERT(o.board >= 0);
    for (const auto& p : *obs.corners[k]) o.pixels.emplace_back(p.x, p.y);
    problem.observations.push_back(std::move(o));
  }
  return problem;
}

// 6. The adjusted rig must fit: overall, and each camera about as well as it fits its boards
// alone (much worse in the rig means the cameras disagree about the boards: wrong board size
// for some, a camera moved mid-capture).
void check_consistent(const CalibrationOptions& options,
                      const std::vector<IntrinsicsResult>& intrinsics, const BundleResult& adjusted,
                      const std::vector<int>& ids) {
  HULLPOSE_THROW_UNLESS(adjusted.final_rms_px <= options.max_rms_px,
                        "the calibrated rig is inconsistent: RMS reprojection error "
                            << adjusted.final_rms_px << " px after bundle adjustment exceeds "
                            << options.max_rms_px
                            << " px (wrong board size, moving cameras, or unsynchronised images?)");
  std::vector<std::string> inconsistent;
  for (size_t c = 0; c < intrinsics.size(); ++c) {
    const double alone = intrinsics[c].rms_px;
    const double in_rig = adjusted.camera_rms_px[c];
    if (in_rig > kMaxRigToIntrinsicRms * alone + kRigRmsSlackPx) {
      std::ostringstream s;
      s << "camera " << ids[c] << " (" << std::setprecision(3) << in_rig << " px in the rig, "
        << alone << " px alone)";
      inconsistent.push_back(s.str());
    }
  }
  if (inconsistent.empty()) return;
  std::string list;
  for (const auto& s : inconsistent) list += (list.empty() ? "" : ", ") + s;
  HULLPOSE_THROW("the calibrated rig is inconsistent: "
                 << list << " (wrong board size, a camera moved, or unsynchronised images?)");
}

}  // namespace

CalibrationResult RigCalibrator::solve() const {
  HULLPOSE_THROW_UNLESS(!cameras_.empty(), "no images were given");
  for (const auto& [key, marks] : options_.marked_corners)
    HULLPOSE_THROW_UNLESS(marks_used_.count(key) != 0, "corners were marked for camera "
                                                           << key.first << ", view " << key.second
                                                           << ", but no such image was given");
  std::vector<int> ids;
  const std::vector<IntrinsicsResult> intrinsics =
      calibrate_intrinsics(cameras_, options_.known_intrinsics, ids);
  const int n_cams = static_cast<int>(ids.size());
  const int n_views = static_cast<int>(views_.size());

  const Observations obs = board_poses(intrinsics, view_index_);
  const std::vector<int> floors = floor_views(options_, view_index_, obs.poses);
  const int root = root_camera(obs.poses, floors.front());
  const Linkage link = link_cameras(n_cams, n_views, obs.poses, root);
  check_linked(link, ids, root);

  BundleProblem problem =
      bundle_problem(options_, intrinsics, obs, floors, link, n_views);  // adjusted in place
  BundleOptions ba;
  ba.refine_intrinsics = options_.refine_intrinsics && options_.known_intrinsics.empty();
  ba.refine_k3 = options_.intrinsics.estimate_k3;
  const BundleResult adjusted = bundle_adjust(problem, ba);
  HULLPOSE_LOG(Calibrate, Info) << "bundle adjustment: rms " << adjusted.initial_rms_px << " -> "
                                << adjusted.final_rms_px << " px in " << adjusted.iterations
                                << " iterations";
  check_consistent(options_, intrinsics, adjusted, ids);

  CalibrationResult result;
  result.floor_boards = static_cast<int>(floors.size());
  result.rms_px = adjusted.final_rms_px;
  result.initial_rms_px = adjusted.initial_rms_px;
  result.iterations = adjusted.iterations;
  result.rig.rig_id = options_.rig_id;
  for (int c = 0; c < n_cams; ++c) {
    const auto cs = static_cast<size_t>(c);
    result.rig.cameras.push_back(problem.cameras[cs]);
    result.corners += adjusted.camera_corners[cs];
    const auto& in = intrinsics[cs];
    const auto& calibrator = cameras_.at(ids[cs]);
    CameraReport r;
    r.id = ids[cs];
    r.images = calibrator.views_seen();
    r.boards_found = calibrator.views_found();
    r.views_kept = static_cast<int>(in.kept.size());
    r.rejected_views = in.rejected;
    r.shared_views = link.shared_views[cs];
    r.coverage = in.coverage;
    r.intrinsic_rms_px = in.rms_px;
    r.rig_rms_px = adjusted.camera_rms_px[cs];
    result.cameras.push_back(r);
  }
  const int min_cams = options_.volume_min_cameras > 0 ? options_.volume_min_cameras : n_cams;
  result.rig.volume = common_view_volume(result.rig.cameras, min_cams);
  result.rig.validate();
  return result;
}

void print_report(std::ostream& out, const CalibrationResult& r) {
  out << "camera  images  boards  kept  shared  coverage  rms-intrinsic  rms-rig   fx       fy     "
         "  cx      cy\n";
  for (size_t i = 0; i < r.cameras.size(); ++i) {
    const auto& c = r.cameras[i];
    const auto& m = r.rig.cameras[i];
    out << std::left << std::setw(8) << ("cam" + std::to_string(c.id)) << std::right << std::setw(6)
        << c.images << std::setw(8) << c.boards_found << std::setw(6) << c.views_kept
        << std::setw(8) << c.shared_views << std::setw(9) << std::fixed << std::setprecision(0)
        << 100 * c.coverage << "%" << std::setprecision(3) << std::setw(15) << c.intrinsic_rms_px
        << std::setw(9) << c.rig_rms_px << std::setprecision(1) << std::setw(9) << m.fx
        << std::setw(9) << m.fy << std::setw(8) << m.cx << std::setw(8) << m.cy << "\n";
    if (!c.rejected_views.empty()) {
      out << "        rejected views:";
      for (const auto& v : c.rejected_views) out << " " << v;
      out << "\n";
    }
  }
  out << std::setprecision(3) << "rig '" << r.rig.rig_id << "': " << r.cameras.size()
      << " cameras, " << r.corners << " corners, RMS " << r.initial_rms_px << " px chained -> "
      << r.rms_px << " px after bundle adjustment (" << r.iterations << " iterations), "
      << r.floor_boards << (r.floor_boards == 1 ? " floor board" : " floor boards")
      << " set the world frame\n"
      << std::setprecision(0) << "capture volume [" << r.rig.volume.min_mm.transpose() << "] .. ["
      << r.rig.volume.max_mm.transpose() << "] mm\n";
}

}  // namespace hullpose::calibrate
