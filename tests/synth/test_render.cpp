#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/synth/render.hpp"
#include "hullpose/synth/rig_gen.hpp"

using namespace hullpose;
using namespace hullpose::synth;

namespace {

CameraModel test_camera(bool distorted) {
  RingRigSpec spec;
  spec.ring_cameras = 1;
  spec.ceiling = false;
  CameraModel c = make_ring_rig(spec).cameras[0];
  if (distorted) c.dist = {-0.25, 0.08, 0.002, -0.001, 0};
  return c;
}

// OpenCV's projection, independent of CameraModel and of the renderer.
std::vector<cv::Point2f> cv_project(const CameraModel& c, const std::vector<cv::Point3d>& world) {
  cv::Mat R, rvec, tvec, K, dist;
  cv::eigen2cv(c.R, R);
  cv::Rodrigues(R, rvec);
  cv::eigen2cv(c.t, tvec);
  cv::eigen2cv(c.K(), K);
  dist = (cv::Mat_<double>(1, 5) << c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4]);
  std::vector<cv::Point2d> px;
  cv::projectPoints(world, rvec, tvec, K, dist, px);
  return {px.begin(), px.end()};
}

}  // namespace

TEST_CASE("a sphere's mask matches its analytic projection within 0.5 px") {
  for (bool distorted : {false, true}) {
    INFO("distorted " << distorted);
    const CameraModel cam = test_camera(distorted);
    ViewRenderer view(cam);
    // Off-centre, so that distortion bends the outline noticeably.
    const Eigen::Vector3d centre(-600, 900, 1700);
    const double r = 250;
    cv::Mat mask;
    view.render_mask({Primitive::sphere(centre, r, Material::Skin)}, mask);

    // The limb: the circle where viewing rays graze the sphere, projected by OpenCV.
    const Eigen::Vector3d o = cam.centre(), n = (centre - o).normalized();
    const double L = (centre - o).norm();
    const Eigen::Vector3d limb_c = centre - n * (r * r / L);
    const double rho = r * std::sqrt(L * L - r * r) / L;
    const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    std::vector<cv::Point3d> limb;
    for (int i = 0; i < 1440; ++i) {
      const double a = 2 * M_PI * i / 1440;
      const Eigen::Vector3d p = limb_c + rho * (std::cos(a) * e1 + std::sin(a) * e2);
      limb.emplace_back(p.x(), p.y(), p.z());
    }
    const std::vector<cv::Point2f> outline = cv_project(cam, limb);
    const cv::Rect box = cv::boundingRect(outline) + cv::Size(40, 40) - cv::Point(20, 20);
    int inside = 0, checked = 0;
    for (int v = std::max(0, box.y); v < std::min(cam.height, box.br().y); ++v)
      for (int u = std::max(0, box.x); u < std::min(cam.width, box.br().x); ++u) {
        const double d = cv::pointPolygonTest(outline, cv::Point2f(u, v), true);
        if (std::abs(d) <= 0.5) continue;  // within half a pixel of the outline: either is right
        ++checked;
        inside += d > 0;
        if ((mask.at<uint8_t>(v, u) == 255) != (d > 0))
          FAIL("pixel " << u << "," << v << " distance " << d);
      }
    CHECK(inside > 1000);
    CHECK(checked > 3000);
    // Nothing outside the checked box.
    cv::Mat outside = mask.clone();
    outside(box & cv::Rect(0, 0, cam.width, cam.height)).setTo(0);
    CHECK(cv::countNonZero(outside) == 0);
  }
}

TEST_CASE("a capsule's mask matches its analytic projection within 0.5 px") {
  for (bool distorted : {false, true}) {
    INFO("distorted " << distorted);
    const CameraModel cam = test_camera(distorted);
    ViewRenderer view(cam);
    const Eigen::Vector3d a(-300, -500, 400), b(400, 300, 1500);
    const double r = 90;
    cv::Mat mask;
    view.render_mask({Primitive::capsule(a, b, r, Material::Skin)}, mask);

    // Rays from OpenCV's undistortion; for a distorted camera the renderer uses it too, the
    // undistorted case checks the renderer's own ray map independently.
    const std::vector<cv::Point2f> ends =
        cv_project(cam, {{a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()}});
    cv::Rect box = cv::boundingRect(ends);
    box = (box + cv::Size(160, 160) - cv::Point(80, 80)) & cv::Rect(0, 0, cam.width, cam.height);
    std::vector<cv::Point2f> pixels;
    for (int v = box.y; v < box.br().y; ++v)
      for (int u = box.x; u < box.br().x; ++u) pixels.emplace_back(u, v);
    cv::Mat K, dist;
    cv::eigen2cv(cam.K(), K);
    dist =
        (cv::Mat_<double>(1, 5) << cam.dist[0], cam.dist[1], cam.dist[2], cam.dist[3], cam.dist[4]);
    std::vector<cv::Point2f> norm;
    cv::undistortPoints(
        pixels, norm, K, dist, cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-12));
    // Distance from the ray to the segment by golden-section search over the segment
    // parameter (the squared distance is convex in it); plain doubles keep debug builds fast.
    const Eigen::Vector3d o = cam.centre();
    int inside = 0, checked = 0;
    for (size_t k = 0; k < pixels.size(); ++k) {
      const Eigen::Vector3d dv =
          (cam.R.transpose() * Eigen::Vector3d(norm[k].x, norm[k].y, 1)).normalized();
      const double d[3] = {dv.x(), dv.y(), dv.z()};
      double depth = 0;
      auto dist2 = [&](double s, double& t) {
        double p[3], pd = 0, pp = 0;
        for (int i = 0; i < 3; ++i) p[i] = a[i] + s * (b[i] - a[i]) - o[i], pd += p[i] * d[i];
        t = pd;
        for (int i = 0; i < 3; ++i) pp += (p[i] - pd * d[i]) * (p[i] - pd * d[i]);
        return pp;
      };
      double lo = 0, hi = 1;
      const double g = (std::sqrt(5.0) - 1) / 2;
      for (int it = 0; it < 60; ++it) {
        const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
        double t1, t2;
        if (dist2(m1, t1) < dist2(m2, t2))
          hi = m2;
        else
          lo = m1;
      }
      const double best = dist2(0.5 * (lo + hi), depth);
      // Half a pixel at this depth, in mm (plus the sampling error of the segment).
      const double half_px_mm = 0.5 * depth / cam.fx;
      const double gap = std::sqrt(best) - r;
      if (std::abs(gap) <= half_px_mm + 0.001) continue;
      ++checked;
      inside += gap < 0;
      const bool rendered = mask.at<uint8_t>(cvRound(pixels[k].y), cvRound(pixels[k].x)) == 255;
      if (rendered != (gap < 0))
        FAIL("pixel " << pixels[k].x << "," << pixels[k].y << " gap " << gap << " mm");
    }
    CHECK(inside > 1000);
    cv::Mat outside = mask.clone();
    outside(box).setTo(0);
    CHECK(cv::countNonZero(outside) == 0);
  }
}

TEST_CASE(
    "an ellipsoid renders as the union-free analytic conic; layers pick the nearest surface") {
  const CameraModel cam = test_camera(false);
  ViewRenderer view(cam);
  // An ellipsoid that is a sphere in disguise must render exactly like the sphere.
  const Eigen::Vector3d c(0, 0, 1000);
  Eigen::Matrix3d axes =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() * 200.0;
  cv::Mat m1, m2;
  view.render_mask({Primitive::ellipsoid(c, axes, Material::Shirt)}, m1);
  view.render_mask({Primitive::sphere(c, 200, Material::Shirt)}, m2);
  CHECK(cv::norm(m1, m2, cv::NORM_L1) <=
        255 * 4);  // float rounding may flip a boundary pixel or two
  // Two spheres, the nearer one in front: its material wins where they overlap.
  const Eigen::Vector3d towards_cam = (cam.centre() - c).normalized();
  cv::Mat mask, material, facing;
  view.render_layers({Primitive::sphere(c, 200, Material::Shirt),
                      Primitive::sphere(c + towards_cam * 500, 100, Material::Skin)},
                     mask, material, facing);
  const auto px = cam.project(c);
  REQUIRE(px);
  CHECK(material.at<uint8_t>(cvRound(px->y()), cvRound(px->x())) ==
        static_cast<uint8_t>(Material::Skin));
  CHECK(facing.at<float>(cvRound(px->y()), cvRound(px->x())) > 0.99f);
  CHECK(cv::countNonZero(mask) == cv::countNonZero(material != 255));
}
