#include "hullpose/synth/render.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>

namespace hullpose::synth {

struct ViewRenderer::Prepared {
  Primitive::Kind kind;
  Material material;
  int u0, u1, v0, v1;  // inclusive pixel bounds
  // Capsule, camera frame: A, u = B - A, r^2 and constants of the closest-approach formula.
  Eigen::Vector3f A, u;
  float r2, aa, uu, ua;
  // Ellipsoid: M maps the camera frame to the unit sphere around the centre; o = -M c.
  Eigen::Matrix3f M;
  Eigen::Vector3f o;
  float oo;
};

namespace {

constexpr double kNear = 10;  // mm: primitives closer to the camera plane get the whole image

// Normalised-coordinate extent of a sphere seen from the origin (camera frame), per axis.
bool sphere_extent(const Eigen::Vector3d& c, double r, double& x0, double& x1, double& y0,
                   double& y1) {
  if (c.z() - r < kNear) return false;
  auto range = [&](double a, double& lo, double& hi) {
    const double theta = std::atan2(a, c.z());
    const double delta = std::asin(std::min(1.0, r / std::hypot(a, c.z())));
    lo = std::tan(theta - delta);
    hi = std::tan(theta + delta);
  };
  range(c.x(), x0, x1);
  range(c.y(), y0, y1);
  return true;
}

}  // namespace

ViewRenderer::ViewRenderer(const CameraModel& camera) : camera_(camera) {
  rays_.create(camera.height, camera.width, CV_32FC2);
  for (int v = 0; v < camera.height; ++v) {
    auto* row = rays_.ptr<cv::Vec2f>(v);
    for (int u = 0; u < camera.width; ++u)
      row[u] = cv::Vec2f(static_cast<float>((u - camera.cx) / camera.fx),
                         static_cast<float>((v - camera.cy) / camera.fy));
  }
  if (camera.has_distortion()) {
    // OpenCV's iterative undistortion, run to convergence (the default stops after 5 steps).
    std::vector<cv::Point2f> pixels;
    pixels.reserve(rays_.total());
    for (int v = 0; v < camera.height; ++v)
      for (int u = 0; u < camera.width; ++u)
        pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
    const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    const cv::Matx<double, 1, 5> dist(camera.dist[0], camera.dist[1], camera.dist[2],
                                      camera.dist[3], camera.dist[4]);
    cv::undistortPoints(
        pixels, rays_.reshape(2, static_cast<int>(rays_.total())), K, dist, cv::noArray(),
        cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  }
}

cv::Vec3f ViewRenderer::ray(int u, int v) const {
  const cv::Vec2f xn = rays_.at<cv::Vec2f>(v, u);
  return cv::normalize(cv::Vec3f(xn[0], xn[1], 1.f));
}

bool ViewRenderer::prepare(const Primitive& p, Prepared& q) const {
  const CameraModel& c = camera_;
  q.kind = p.kind;
  q.material = p.material;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool bounded = false;
  if (p.kind == Primitive::Kind::Capsule) {
    const Eigen::Vector3d a = c.R * p.a + c.t, b = c.R * p.b + c.t;
    q.A = a.cast<float>();
    q.u = (b - a).cast<float>();
    q.r2 = static_cast<float>(p.r * p.r);
    q.aa = static_cast<float>(a.squaredNorm());
    q.uu = static_cast<float>((b - a).squaredNorm());
    q.ua = static_cast<float>((b - a).dot(a));
    // The capsule is the convex hull of its end spheres; so is its projection.
    double ax0, ax1, ay0, ay1, bx0, bx1, by0, by1;
    bounded =
        sphere_extent(a, p.r, ax0, ax1, ay0, ay1) && sphere_extent(b, p.r, bx0, bx1, by0, by1);
    x0 = std::min(ax0, bx0), x1 = std::max(ax1, bx1), y0 = std::min(ay0, by0),
    y1 = std::max(ay1, by1);
  } else {
    const Eigen::Vector3d centre = c.R * p.a + c.t;
    const Eigen::Matrix3d M = (c.R * p.axes).inverse();
    q.M = M.cast<float>();
    q.o = (-M * centre).cast<float>();
    q.oo = q.o.squaredNorm();
    bounded = sphere_extent(centre, p.r, x0, x1, y0, y1);
  }
  if (!bounded) {
    q.u0 = 0, q.v0 = 0, q.u1 = c.width - 1, q.v1 = c.height - 1;
    return true;
  }
  double u0, u1, v0, v1;
  if (!c.has_distortion()) {
    u0 = c.fx * x0 + c.cx, u1 = c.fx * x1 + c.cx, v0 = c.fy * y0 + c.cy, v1 = c.fy * y1 + c.cy;
  } else {
    // The distorted image of the box is bounded by the image of its outline; sample it densely
    // and pad, as the outline bends between samples.
    u0 = v0 = std::numeric_limits<double>::infinity();
    u1 = v1 = -u0;
    constexpr int kSteps = 16;
    for (int i = 0; i <= kSteps; ++i) {
      const double f = static_cast<double>(i) / kSteps;
      for (const Eigen::Vector2d& xn :
           {Eigen::Vector2d(x0 + f * (x1 - x0), y0), Eigen::Vector2d(x0 + f * (x1 - x0), y1),
            Eigen::Vector2d(x0, y0 + f * (y1 - y0)), Eigen::Vector2d(x1, y0 + f * (y1 - y0))}) {
        const Eigen::Vector2d px = c.distort_normalised(xn);
        u0 = std::min(u0, px.x()), u1 = std::max(u1, px.x()), v0 = std::min(v0, px.y()),
        v1 = std::max(v1, px.y());
      }
    }
    u0 -= 2, v0 -= 2, u1 += 2, v1 += 2;
  }
  const double big = 1e6;
  q.u0 = static_cast<int>(std::ceil(std::clamp(u0, -big, big)));
  q.u1 = static_cast<int>(std::floor(std::clamp(u1, -big, big)));
  q.v0 = static_cast<int>(std::ceil(std::clamp(v0, -big, big)));
  q.v1 = static_cast<int>(std::floor(std::clamp(v1, -big, big)));
  q.u0 = std::max(q.u0, 0), q.v0 = std::max(q.v0, 0);
  q.u1 = std::min(q.u1, c.width - 1), q.v1 = std::min(q.v1, c.height - 1);
  return q.u0 <= q.u1 && q.v0 <= q.v1;
}

template <bool kLayers>
void ViewRenderer::raster(const std::vector<Primitive>& primitives, cv::Mat& mask,
                          cv::Mat* material, cv::Mat* facing) {
  const int W = camera_.width, H = camera_.height;
  mask.create(H, W, CV_8UC1);
  mask.setTo(0);
  if constexpr (kLayers) {
    material->create(H, W, CV_8UC1);
    material->setTo(255);
    facing->create(H, W, CV_32FC1);
    depth_.create(H, W, CV_32FC1);
    depth_.setTo(cv::Scalar::all(std::numeric_limits<double>::infinity()));
  }
  Prepared q;
  for (const Primitive& p : primitives) {
    if (!prepare(p, q)) continue;
    for (int v = q.v0; v <= q.v1; ++v) {
      const auto* ray = rays_.ptr<cv::Vec2f>(v);
      uint8_t* m = mask.ptr<uint8_t>(v);
      for (int x = q.u0; x <= q.u1; ++x) {
        // Ray d = (xn, yn, 1): its parameter is the depth along the optical axis.
        const float dx = ray[x][0], dy = ray[x][1];
        const float dd = dx * dx + dy * dy + 1.f;
        bool hit;
        float depth = 0, face = 0;
        if (q.kind == Primitive::Kind::Capsule) {
          // Closest approach of the ray and the segment A + s u, s in [0, 1].
          const float b = q.u.x() * dx + q.u.y() * dy + q.u.z();
          const float e = q.A.x() * dx + q.A.y() * dy + q.A.z();
          const float den = q.uu * dd - b * b;
          float s = den > 1e-6f * q.uu * dd ? (b * e - dd * q.ua) / den : 0.f;
          s = std::clamp(s, 0.f, 1.f);
          const float t = (e + s * b) / dd;
          const float dist2 = q.aa + 2.f * s * q.ua + s * s * q.uu - t * t * dd;
          hit = dist2 <= q.r2 && t > 0.f;
          if constexpr (kLayers) {
            const float rest = std::max(0.f, q.r2 - dist2);
            depth = t - std::sqrt(rest / dd);
            face = std::sqrt(rest / q.r2);
          }
        } else {
          const Eigen::Vector3f d = q.M.col(0) * dx + q.M.col(1) * dy + q.M.col(2);
          const float od = q.o.dot(d), d2 = d.squaredNorm();
          const float disc = od * od - d2 * (q.oo - 1.f);
          hit = disc >= 0.f && od < 0.f;
          if constexpr (kLayers) {
            const float root = std::sqrt(std::max(0.f, disc));
            depth = (-od - root) / d2;
            face = root / std::sqrt(d2);
          }
        }
        if (!hit) continue;
        m[x] = 255;
        if constexpr (kLayers) {
          float& z = depth_.ptr<float>(v)[x];
          if (depth < z) {
            z = depth;
            material->ptr<uint8_t>(v)[x] = static_cast<uint8_t>(q.material);
            facing->ptr<float>(v)[x] = std::min(1.f, face);
          }
        }
      }
    }
  }
}

void ViewRenderer::render_mask(const std::vector<Primitive>& primitives, cv::Mat& mask) {
  raster<false>(primitives, mask, nullptr, nullptr);
}

void ViewRenderer::render_layers(const std::vector<Primitive>& primitives, cv::Mat& mask,
                                 cv::Mat& material, cv::Mat& facing) {
  raster<true>(primitives, mask, &material, &facing);
}

}  // namespace hullpose::synth
