#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <random>

#include "hullpose/common/camera.hpp"

using namespace hullpose;

namespace {

CameraModel random_camera(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  CameraModel c;
  c.width = 800;
  c.height = 600;
  c.fx = 600 + 200 * u(rng);
  c.fy = c.fx * (1 + 0.01 * u(rng));
  c.cx = 400 + 20 * u(rng);
  c.cy = 300 + 20 * u(rng);
  c.dist = {0.2 * u(rng), 0.05 * u(rng), 0.002 * u(rng), 0.002 * u(rng), 0.01 * u(rng)};
  // One draw per statement, last argument first: the order x86-64 GCC evaluated them in when
  // they were one call's arguments (unspecified in C++; aarch64 goes the other way).
  const double az = u(rng), ay = u(rng), ax = u(rng), angle = M_PI * u(rng);
  c.R = Eigen::AngleAxisd(angle, Eigen::Vector3d(ax, ay, az).normalized()).toRotationMatrix();
  const double tz = 4000 + 500 * u(rng), ty = 500 * u(rng), tx = 500 * u(rng);
  c.t = Eigen::Vector3d(tx, ty, tz);
  return c;
}

}  // namespace

TEST_CASE("projection equals cv::projectPoints within 1e-6 px") {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1, 1);
  int compared = 0;
  for (int cam = 0; cam < 50; ++cam) {
    const CameraModel c = random_camera(rng);
    cv::Mat K, R, rvec, tvec, dist(1, 5, CV_64F, const_cast<double*>(c.dist.data()));
    cv::eigen2cv(c.K(), K);
    cv::eigen2cv(c.R, R);
    cv::Rodrigues(R, rvec);
    cv::eigen2cv(c.t, tvec);
    std::vector<cv::Point3d> pts;
    std::vector<Eigen::Vector3d> world;
    for (int i = 0; i < 100; ++i) {
      // Points in front of the camera, inside a ~40 degree cone so distortion stays sane.
      const double y = 0.35 * u(rng), x = 0.35 * u(rng);  // y first: see random_camera
      const Eigen::Vector3d pc(x, y, 1.0);
      const Eigen::Vector3d pw = c.R.transpose() * (pc * (2000 + 1500 * u(rng)) - c.t);
      world.push_back(pw);
      pts.emplace_back(pw.x(), pw.y(), pw.z());
    }
    std::vector<cv::Point2d> ref;
    cv::projectPoints(pts, rvec, tvec, K, dist, ref);
    for (size_t i = 0; i < world.size(); ++i) {
      const auto p = c.project(world[i]);
      REQUIRE(p.has_value());
      CHECK(std::abs(p->x() - ref[i].x) < 1e-6);
      CHECK(std::abs(p->y() - ref[i].y) < 1e-6);
      ++compared;
    }
  }
  CHECK(compared == 5000);
}

TEST_CASE("back-projection inverts projection") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int cam = 0; cam < 20; ++cam) {
    const CameraModel c = random_camera(rng);
    for (int i = 0; i < 50; ++i) {
      const double y = 300 + 250 * u(rng), x = 400 + 350 * u(rng);  // y first: see random_camera
      const Eigen::Vector2d px(x, y);
      const double depth = 3000 + 1000 * u(rng);
      const Eigen::Vector3d w = c.back_project(px, depth);
      CHECK((*c.project(w) - px).norm() < 1e-6);
      const Eigen::Vector3d ray = c.back_project(px);
      CHECK((ray - (w - c.centre()).normalized()).norm() < 1e-9);
    }
  }
}

TEST_CASE("points behind the camera do not project") {
  CameraModel c;
  c.fx = c.fy = 500;
  c.cx = 400;
  c.cy = 300;
  CHECK_FALSE(c.project({0, 0, -100}).has_value());
  CHECK_FALSE(c.project({0, 0, 0}).has_value());
  CHECK(c.project({0, 0, 100}).has_value());
}
