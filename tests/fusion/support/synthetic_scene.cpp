#include "synthetic_scene.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace hullpose::fusion::testing {

namespace {

CameraModel look_at(int id, const Eigen::Vector3d& centre, const Eigen::Vector3d& target,
                    const Eigen::Vector3d& up, int width, int height) {
  CameraModel c;
  c.id = id;
  c.name = "cam" + std::to_string(id);
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.9 * width;
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  c.dist = {-0.04, 0.01, 0, 0, 0};
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  c.R.row(0) = x;
  c.R.row(1) = y;
  c.R.row(2) = z;
  c.t = -c.R * centre;
  return c;
}

double point_segment_distance(const Eigen::Vector3d& p, const Capsule& c) {
  const Eigen::Vector3d ab = c.b - c.a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - c.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (c.a + t * ab)).norm();
}

}  // namespace

Rig thesis_like_rig(int width, int height, int cameras) {
  Rig rig;
  rig.rig_id = "test-thesis-like";
  rig.volume.min_mm = {-1200, -1200, 0};
  rig.volume.max_mm = {1200, 1200, 2200};
  const Eigen::Vector3d target(0, 0, 1000);
  for (int i = 0; i < std::min(cameras, 7); ++i) {
    const double a = 2 * M_PI * i / 7 + 0.3;
    rig.cameras.push_back(look_at(i, {4000 * std::cos(a), 4000 * std::sin(a), 2000}, target,
                                  {0, 0, 1}, width, height));
  }
  if (cameras >= 8)
    rig.cameras.push_back(look_at(7, {0, 0, 4500}, {0, 0, 0}, {0, 1, 0}, width, height));
  return rig;
}

std::vector<Capsule> human_capsules(double phase, double yaw, const Eigen::Vector2d& offset) {
  const double swing = std::sin(2 * M_PI * phase);
  const double arm =
      0.35 + 0.9 * (0.5 + 0.5 * std::sin(2 * M_PI * phase + 1.0));  // rad from the body
  std::vector<Capsule> body;
  body.push_back({{0, 0, 920}, {0, 0, 1330}, 150});       // torso
  body.push_back({{0, 0, 1420}, {0, 0, 1520}, 55});       // neck
  body.push_back({{0, 10, 1600}, {0, 10, 1650}, 100});    // head
  body.push_back({{-170, 0, 1390}, {170, 0, 1390}, 65});  // shoulders
  body.push_back({{-100, 0, 900}, {100, 0, 900}, 110});   // pelvis
  for (int side = -1; side <= 1; side += 2) {
    const Eigen::Vector3d shoulder(side * 200, 0, 1390);
    const Eigen::Vector3d elbow =
        shoulder + 280 * Eigen::Vector3d(side * std::sin(arm), 0.3 * swing * side, -std::cos(arm));
    const Eigen::Vector3d hand =
        elbow + 260 * Eigen::Vector3d(side * std::sin(arm + 0.4), 0.2, -std::cos(arm + 0.4));
    body.push_back({shoulder, elbow, 48});
    body.push_back({elbow, hand, 40});
    const Eigen::Vector3d hip(side * 100, 0, 880);
    const Eigen::Vector3d knee = hip + Eigen::Vector3d(side * 15, 120 * swing * side, -400);
    const Eigen::Vector3d ankle(side * 110, -60 * swing * side, 90);
    body.push_back({hip, knee, 75});
    body.push_back({knee, ankle, 52});
    body.push_back({ankle, ankle + Eigen::Vector3d(0, 160, -30), 42});  // foot
  }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d t(offset.x(), offset.y(), 0);
  for (Capsule& c : body) {
    c.a = R * c.a + t;
    c.b = R * c.b + t;
  }
  return body;
}

cv::Mat render_silhouette(const CameraModel& camera, const std::vector<Capsule>& body) {
  cv::Mat mask(camera.height, camera.width, CV_8UC1, cv::Scalar(0));
  // Fibonacci sphere directions.
  constexpr int kSamples = 64;
  std::vector<Eigen::Vector3d> dirs;
  for (int i = 0; i < kSamples; ++i) {
    const double z = 1 - 2 * (i + 0.5) / kSamples;
    const double r = std::sqrt(1 - z * z);
    const double a = i * M_PI * (3 - std::sqrt(5.0));
    dirs.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  for (const Capsule& c : body) {
    std::vector<cv::Point2f> pts;
    for (const Eigen::Vector3d& end : {c.a, c.b})
      for (const Eigen::Vector3d& d : dirs)
        if (const auto p = camera.project(end + c.radius * d))
          pts.emplace_back(static_cast<float>(p->x()), static_cast<float>(p->y()));
    if (pts.size() < 3) continue;
    std::vector<cv::Point2f> hull;
    cv::convexHull(pts, hull);
    std::vector<cv::Point> poly;
    for (const auto& p : hull) poly.emplace_back(cvRound(p.x), cvRound(p.y));
    cv::fillConvexPoly(mask, poly, cv::Scalar(255));
  }
  return mask;
}

std::vector<cv::Mat> render_views(const Rig& rig, const std::vector<Capsule>& body) {
  std::vector<cv::Mat> views;
  for (const CameraModel& c : rig.cameras) views.push_back(render_silhouette(c, body));
  return views;
}

BitGrid voxelise(const VoxelGridSpec& grid, const std::vector<Capsule>& body) {
  BitGrid g(grid.dims);
  for (int z = 0; z < grid.dims.z(); ++z)
    for (int y = 0; y < grid.dims.y(); ++y)
      for (int x = 0; x < grid.dims.x(); ++x) {
        const Eigen::Vector3d p = grid.centre_mm({x, y, z});
        for (const Capsule& c : body)
          if (point_segment_distance(p, c) <= c.radius) {
            g.set(x, y, z);
            break;
          }
      }
  return g;
}

}  // namespace hullpose::fusion::testing
