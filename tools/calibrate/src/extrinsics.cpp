#include "hullpose/calibrate/extrinsics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "hullpose/common/check.hpp"

namespace hullpose::calibrate {
namespace {

// Distance between two relative poses for choosing a consensus: rotation angle scaled so that
// 1 degree weighs like 10 mm, plus the translation difference.
double pose_distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const double angle = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
  return angle * 180.0 / M_PI * 10.0 + (a.translation() - b.translation()).norm();
}

// The candidate closest to all others (a medoid): robust to a few bad board poses.
Eigen::Isometry3d medoid(const std::vector<Eigen::Isometry3d>& candidates) {
  HULLPOSE_ASSERT(!candidates.empty());
  size_t best = 0;
  double best_sum = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < candidates.size(); ++i) {
    double sum = 0;
    for (const auto& other : candidates) sum += pose_distance(candidates[i], other);
    if (sum < best_sum) {
      best_sum = sum;
      best = i;
    }
  }
  return candidates[best];
}

}  // namespace

Linkage link_cameras(int n_cameras, int n_views, const std::vector<PoseObservation>& observations,
                     int root_camera) {
  HULLPOSE_ASSERT(root_camera >= 0 && root_camera < n_cameras);
  const auto nc = static_cast<size_t>(n_cameras);
  std::vector<std::vector<const PoseObservation*>> by_view(static_cast<size_t>(n_views));
  for (const auto& o : observations) {
    HULLPOSE_ASSERT(o.camera >= 0 && o.camera < n_cameras && o.view >= 0 && o.view < n_views);
    by_view[static_cast<size_t>(o.view)].push_back(&o);
  }
  // a_from_b candidates for every ordered camera pair that shared a view.
  std::map<std::pair<int, int>, std::vector<Eigen::Isometry3d>> pair_poses;
  Linkage link;
  link.shared_views.assign(nc, 0);
  for (const auto& seen : by_view) {
    for (const auto* a : seen) {
      if (seen.size() > 1) ++link.shared_views[static_cast<size_t>(a->camera)];
      for (const auto* b : seen)
        if (a->camera != b->camera)
          pair_poses[{a->camera, b->camera}].push_back(a->cam_from_board *
                                                       b->cam_from_board.inverse());
    }
  }
  // Prim's algorithm for a maximum spanning tree: always attach the camera sharing the most
  // views with the tree, so each link rests on as many boards as possible.
  link.linked.assign(nc, false);
  link.root_from_cam.assign(nc, Eigen::Isometry3d::Identity());
  link.linked[static_cast<size_t>(root_camera)] = true;
  for (;;) {
    int best_a = -1, best_b = -1;
    size_t best_weight = 0;
    for (const auto& [pair, poses] : pair_poses) {
      const auto [a, b] = pair;
      if (link.linked[static_cast<size_t>(a)] && !link.linked[static_cast<size_t>(b)] &&
          poses.size() > best_weight) {
        best_weight = poses.size();
        best_a = a;
        best_b = b;
      }
    }
    if (best_a < 0) break;
    link.root_from_cam[static_cast<size_t>(best_b)] =
        link.root_from_cam[static_cast<size_t>(best_a)] * medoid(pair_poses[{best_a, best_b}]);
    link.linked[static_cast<size_t>(best_b)] = true;
  }
  // Each board from the linked camera that saw it best.
  link.root_from_board.assign(static_cast<size_t>(n_views), std::nullopt);
  for (size_t v = 0; v < by_view.size(); ++v) {
    const PoseObservation* best = nullptr;
    for (const auto* o : by_view[v])
      if (link.linked[static_cast<size_t>(o->camera)] && (!best || o->rms_px < best->rms_px))
        best = o;
    if (best)
      link.root_from_board[v] =
          link.root_from_cam[static_cast<size_t>(best->camera)] * best->cam_from_board;
  }
  return link;
}

CaptureVolume common_view_volume(const std::vector<CameraModel>& cameras, int min_cameras,
                                 double step_mm) {
  HULLPOSE_ASSERT(!cameras.empty() && step_mm > 0);
  min_cameras = std::clamp(min_cameras, 1, static_cast<int>(cameras.size()));
  // Far outside the field of view the distortion polynomial can fold points back into the
  // image; accept only points within the undistorted radius of the image corners.
  std::vector<double> max_r2;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& c : cameras) {
    double r2 = 0;
    for (double u : {0.0, static_cast<double>(c.width)})
      for (double v : {0.0, static_cast<double>(c.height)})
        r2 = std::max(r2, c.undistort_pixel({u, v}).squaredNorm());
    max_r2.push_back(r2);
    lo = lo.cwiseMin(c.centre());
    hi = hi.cwiseMax(c.centre());
  }
  // Cameras along walls rather than on a ring see space beyond their own extent (a rig with
  // three cameras on one wall and one on another sees the room behind the fourth): search half
  // the cameras' horizontal extent further on every side.
  const double grow = 0.5 * (hi - lo).head<2>().maxCoeff();
  lo.head<2>().array() -= grow;
  hi.head<2>().array() += grow;
  lo.z() = 0;
  hi.z() = std::max(hi.z(), step_mm);
  Eigen::Vector3d vmin = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d vmax = -vmin;
  const Eigen::Vector3i n = ((hi - lo) / step_mm).array().ceil().cast<int>() + 1;
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Eigen::Vector3d p = lo + step_mm * Eigen::Vector3d(i, j, k);
        // A point inside the box found so far cannot widen it, and a point already missed by
        // more cameras than may miss it cannot count: skipping both changes no result (the
        // crane's and Utrecht's imported rigs are the same bytes) and makes the crane's import
        // 4x faster in the sanitizer build, where it was most of CI's test time (90 -> 21 s).
        if ((p.array() >= vmin.array()).all() && (p.array() <= vmax.array()).all()) continue;
        int seen = 0;
        for (size_t ci = 0;
             ci < cameras.size() && seen + static_cast<int>(cameras.size() - ci) >= min_cameras;
             ++ci) {
          const auto& c = cameras[ci];
          const Eigen::Vector3d pc = c.R * p + c.t;
          if (pc.z() <= 0) continue;
          const Eigen::Vector2d xn(pc.x() / pc.z(), pc.y() / pc.z());
          if (xn.squaredNorm() > max_r2[ci]) continue;
          const Eigen::Vector2d px = c.distort_normalised(xn);
          if (px.x() >= 0 && px.y() >= 0 && px.x() < c.width && px.y() < c.height) ++seen;
        }
        if (seen >= min_cameras) {
          vmin = vmin.cwiseMin(p);
          vmax = vmax.cwiseMax(p);
        }
      }
  HULLPOSE_THROW_UNLESS(vmin.allFinite(),
                        "no point from the floor up to the highest camera is seen by "
                            << min_cameras << " cameras: the cameras share no common view");
  CaptureVolume volume;
  volume.min_mm = vmin;
  volume.max_mm = vmax.cwiseMax(vmin + Eigen::Vector3d::Constant(step_mm));
  return volume;
}

}  // namespace hullpose::calibrate
