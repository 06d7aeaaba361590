#include "hullpose/synth/scene.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <random>

#include "hullpose/common/check.hpp"
#include "hullpose/synth/faults.hpp"

namespace hullpose::synth {
namespace {

uint32_t hash3(int a, int b, int c) {
  uint32_t h = static_cast<uint32_t>(a) * 0x8da6b343u ^ static_cast<uint32_t>(b) * 0xd8163841u ^
               static_cast<uint32_t>(c) * 0xcb1ab31fu;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  return h ^ (h >> 15);
}
double unit(uint32_t h) {
  return (h & 0xffffff) / double(0x1000000);
}

// Does the segment p + t d, t in (0, 1), hit the primitive? (Shadow rays.)
bool segment_hits(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Primitive& q) {
  // Cheap rejection against the bounding sphere first.
  const Eigen::Vector3d c = q.bound_centre() - p;
  const double tc = std::clamp(c.dot(d) / d.squaredNorm(), 0.0, 1.0);
  if ((c - tc * d).squaredNorm() > q.bound_radius() * q.bound_radius()) return false;
  if (q.kind == Primitive::Kind::Capsule) {
    const Eigen::Vector3d A = q.a - p, u = q.b - q.a;
    const double a = u.squaredNorm(), b = u.dot(d), cc = d.squaredNorm(), e = A.dot(d),
                 f = u.dot(A);
    const double den = a * cc - b * b;
    const double s = std::clamp(den > 1e-9 * a * cc ? (b * e - cc * f) / den : 0.0, 0.0, 1.0);
    const double t = std::clamp((e + s * b) / cc, 0.0, 1.0);
    return (A + s * u - t * d).squaredNorm() <= q.r * q.r;
  }
  const Eigen::Matrix3d M = q.axes.inverse();
  const Eigen::Vector3d o = M * (p - q.a), dd = M * d;
  const double od = o.dot(dd), d2 = dd.squaredNorm();
  const double disc = od * od - d2 * (o.squaredNorm() - 1);
  if (disc < 0) return false;
  const double t = (-od - std::sqrt(disc)) / d2;
  return t > 0 && t < 1;
}

}  // namespace

namespace {
constexpr int kNoiseMargin = 32;         // the noise bank is this much larger than the image
constexpr float kNoiseScale = 1 / 64.f;  // grey levels per unit of the 16-bit noise bank
// The shadow map holds the floor, then the four walls (x = +R, y = +R, x = -R, y = -R), stacked
// vertically with a gap so that the blur does not bleed between them.
constexpr int kGap = 4;
std::array<Eigen::Vector3d, 5> plane_normals() {
  return {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(-1, 0, 0), Eigen::Vector3d(0, -1, 0),
          Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
}

// A window of the noise bank at a random offset. y is drawn before x: the order x86-64 GCC
// evaluated them in when both were one call's arguments (unspecified in C++), so seeded
// datasets stay as they were and are the same on every architecture.
cv::Rect noise_window_at(std::mt19937_64& rng, int width, int height) {
  std::uniform_int_distribution<int> offset(0, kNoiseMargin);
  const int y = offset(rng);
  const int x = offset(rng);
  return {x, y, width, height};
}
}  // namespace

Scene::Scene(const SceneOptions& options, uint64_t seed) : options_(options), seed_(seed) {
  HULLPOSE_THROW_UNLESS(
      options.room_half_mm > 1000 && options.room_height_mm > 2500 && options.shadow_texel_mm >= 10,
      "scene: room too small or shadow texels too fine");
  std::mt19937_64 rng(draw_seed(seed, -1, -1, 100));
  auto pick = [&](std::initializer_list<cv::Vec3f> choices) {
    std::uniform_int_distribution<size_t> u(0, choices.size() - 1);
    return *(choices.begin() + u(rng));
  };
  // BGR.
  palette_[static_cast<size_t>(Material::Skin)] =
      pick({{150, 180, 225}, {110, 140, 190}, {70, 95, 140}, {60, 75, 100}});
  palette_[static_cast<size_t>(Material::Hair)] =
      pick({{20, 25, 30}, {30, 60, 100}, {90, 150, 200}, {40, 40, 45}});
  palette_[static_cast<size_t>(Material::Shirt)] = pick({{40, 40, 200},
                                                         {180, 80, 30},
                                                         {40, 160, 40},
                                                         {200, 200, 200},
                                                         {30, 140, 220},
                                                         {140, 40, 120}});
  palette_[static_cast<size_t>(Material::Trousers)] =
      pick({{90, 50, 20}, {40, 40, 40}, {120, 140, 150}, {60, 90, 60}});
  palette_[static_cast<size_t>(Material::Shoes)] =
      pick({{25, 25, 25}, {230, 230, 230}, {40, 60, 110}});
  // A ceiling lamp (floor shadows) and a side lamp (wall shadows).
  const double R = options.room_half_mm;
  lights_ = {{0.2 * R, -0.15 * R, options.room_height_mm - 300}, {-0.7 * R, -0.45 * R, 2500}};
  light_weight_ = {0.6, 0.4};
}

void Scene::shadows(const std::vector<Primitive>& primitives, cv::Mat& atlas) const {
  const double R = options_.room_half_mm, H = options_.room_height_mm, s = options_.shadow_texel_mm;
  const int n = static_cast<int>(std::ceil(2 * R / s)), h = static_cast<int>(std::ceil(H / s));
  atlas.create(n + 4 * (h + kGap) + kGap, n, CV_32FC1);
  atlas.setTo(0);
  if (primitives.empty()) return;
  // The avatar's bounding box: its shadow on a plane lies inside the box's projection from the
  // lamp, so only those texels are ray-traced (the rest of the room stays lit).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Primitive& q : primitives) {
    lo = lo.cwiseMin(q.bound_centre() - Eigen::Vector3d::Constant(q.bound_radius()));
    hi = hi.cwiseMax(q.bound_centre() + Eigen::Vector3d::Constant(q.bound_radius()));
  }
  // Bounding spheres of the feet reach below the floor: nothing there casts a shadow.
  lo = lo.cwiseMax(Eigen::Vector3d(-R, -R, 0));
  hi = hi.cwiseMin(Eigen::Vector3d(R, R, H));
  const auto normals = plane_normals();
  for (int tile = 0; tile < 5; ++tile) {
    const int row0 = tile == 0 ? 0 : n + kGap + (tile - 1) * (h + kGap);
    const int rows = tile == 0 ? n : h;
    const Eigen::Vector3d normal = normals[static_cast<size_t>(tile)];
    // World point of texel (c, r) and texel coordinates (c, r) of a world point on this plane.
    auto world = [&](double c, double r) -> Eigen::Vector3d {
      const double a = -R + (c + 0.5) * s, b = tile == 0 ? -R + (r + 0.5) * s : (r + 0.5) * s;
      switch (tile) {
        case 0:
          return {a, b, 0};
        case 1:
          return {R, a, b};
        case 2:
          return {a, R, b};
        case 3:
          return {-R, a, b};
        default:
          return {a, -R, b};
      }
    };
    auto texel = [&](const Eigen::Vector3d& p) -> Eigen::Vector2d {
      const double a = tile == 0 || tile == 2 || tile == 4 ? p.x() : p.y();
      const double b = tile == 0 ? p.y() + R : p.z();
      return {(a + R) / s - 0.5, b / s - 0.5};
    };
    const Eigen::Vector3d on_plane = world(0, 0);
    for (size_t l = 0; l < lights_.size(); ++l) {
      const Eigen::Vector3d& L = lights_[l];
      if ((L - on_plane).dot(normal) <= 0) continue;  // the lamp is behind this surface
      double c0 = 0, c1 = n - 1, r0 = 0, r1 = rows - 1;
      int hits = 0;
      Eigen::Vector2d tlo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()),
                      thi = -tlo;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(),
                                     (k & 4) ? hi.z() : lo.z());
        const Eigen::Vector3d d = corner - L;
        const double along = d.dot(normal);
        const double t = along < 0 ? (on_plane - L).dot(normal) / along : -1;
        if (t < 0.999) continue;  // the corner's ray from the lamp misses the plane
        ++hits;
        const Eigen::Vector2d tc = texel(L + t * d);
        tlo = tlo.cwiseMin(tc);
        thi = thi.cwiseMax(tc);
      }
      if (hits == 0) continue;  // the avatar casts no shadow on this plane
      if (hits == 8) {
        c0 = std::max(c0, std::floor(tlo.x()) - 1), c1 = std::min(c1, std::ceil(thi.x()) + 1);
        r0 = std::max(r0, std::floor(tlo.y()) - 1), r1 = std::min(r1, std::ceil(thi.y()) + 1);
      }
      for (int r = static_cast<int>(r0); r <= static_cast<int>(r1); ++r) {
        float* out = atlas.ptr<float>(row0 + r);
        for (int c = static_cast<int>(c0); c <= static_cast<int>(c1); ++c) {
          const Eigen::Vector3d p = world(c, r);
          const Eigen::Vector3d d = L - p;
          for (const Primitive& q : primitives)
            if (segment_hits(p, d, q)) {
              out[c] += static_cast<float>(light_weight_[l]);
              break;
            }
        }
      }
    }
  }
  cv::GaussianBlur(atlas, atlas, cv::Size(0, 0), 1.5);
}

Scene::Backdrop Scene::backdrop(const ViewRenderer& view) const {
  const CameraModel& cam = view.camera();
  const double R = options_.room_half_mm, H = options_.room_height_mm, s = options_.shadow_texel_mm;
  const int n = static_cast<int>(std::ceil(2 * R / s)), h = static_cast<int>(std::ceil(H / s));
  Backdrop b;
  b.colour.create(cam.height, cam.width, CV_32FC3);
  b.shadow_map.create(cam.height, cam.width, CV_32FC2);
  const Eigen::Vector3d o = cam.centre();
  const Eigen::Matrix3d Rt = cam.R.transpose();
  static const cv::Vec3f kWalls[4] = {
      {170, 185, 195}, {150, 170, 160}, {185, 175, 160}, {160, 160, 175}};
  for (int v = 0; v < cam.height; ++v) {
    auto* colour = b.colour.ptr<cv::Vec3f>(v);
    auto* map = b.shadow_map.ptr<cv::Vec2f>(v);
    for (int u = 0; u < cam.width; ++u) {
      const cv::Vec3f r = view.ray(u, v);
      const Eigen::Vector3d d = Rt * Eigen::Vector3f(r[0], r[1], r[2]).cast<double>();
      // Nearest of floor, ceiling and the four walls.
      double best = std::numeric_limits<double>::infinity();
      int plane = -1;
      auto consider = [&](int id, double t) {
        if (t > 0 && t < best) best = t, plane = id;
      };
      if (d.z() < 0) consider(0, -o.z() / d.z());
      if (d.z() > 0) consider(5, (H - o.z()) / d.z());
      if (d.x() > 0) consider(1, (R - o.x()) / d.x());
      if (d.y() > 0) consider(2, (R - o.y()) / d.y());
      if (d.x() < 0) consider(3, (-R - o.x()) / d.x());
      if (d.y() < 0) consider(4, (-R - o.y()) / d.y());
      const Eigen::Vector3d p = o + best * d;
      cv::Vec3f c;
      double a = 0, z = 0;  // coordinates along the surface (mm)
      if (plane == 0) {
        // Floor: 500 mm tiles with grout and per-tile tint, plus a fine mottle.
        const int ix = static_cast<int>(std::floor(p.x() / 500)),
                  iy = static_cast<int>(std::floor(p.y() / 500));
        const double fx = p.x() - 500 * ix, fy = p.y() - 500 * iy;
        const double tint = 20 * unit(hash3(ix, iy, 1)) - 10;
        const double mottle = 12 * unit(hash3(static_cast<int>(std::floor(p.x() / 70)),
                                              static_cast<int>(std::floor(p.y() / 70)), 2)) -
                              6;
        const bool grout = fx < 12 || fy < 12;
        const double g = grout ? 95 : 150 + tint + mottle;
        c = cv::Vec3f(static_cast<float>(g * 0.92), static_cast<float>(g),
                      static_cast<float>(g * 1.05));
        a = p.x(), z = p.y();
      } else if (plane == 5) {
        c = cv::Vec3f(205, 205, 205);
      } else {
        a = plane == 1 || plane == 3 ? p.y() : p.x();
        z = p.z();
        c = kWalls[plane - 1];
        const int ia = static_cast<int>(std::floor(a / 1000)),
                  iz = static_cast<int>(std::floor(z / 1000));
        const double fa = a - 1000 * ia, fz = z - 1000 * iz;
        const uint32_t cell = hash3(ia, iz, plane);
        if (z < 150) {
          c = cv::Vec3f(60, 70, 80);  // skirting board
        } else if (iz >= 1 && iz <= 2 && unit(cell) < 0.35 && fa > 150 && fa < 850 && fz > 150 &&
                   fz < 850) {
          c = cv::Vec3f(static_cast<float>(60 + 150 * unit(hash3(ia, iz, 7))),
                        static_cast<float>(60 + 150 * unit(hash3(ia, iz, 8))),
                        static_cast<float>(60 + 150 * unit(hash3(ia, iz, 9))));  // a poster
        } else if (std::fmod(a + 10 * R, 1200) < 15) {
          c *= 0.8f;  // panel seams
        }
        c *= static_cast<float>(0.97 + 0.06 * unit(hash3(static_cast<int>(a / 40),
                                                         static_cast<int>(z / 40), plane + 20)));
      }
      colour[u] = c;
      // Shadow-map coordinates of this point (texel centres at integer positions).
      float mc = -100, mr = -100;
      if (plane == 0) {
        mc = static_cast<float>((a + R) / s - 0.5), mr = static_cast<float>((z + R) / s - 0.5);
      } else if (plane >= 1 && plane <= 4) {
        mc = static_cast<float>((a + R) / s - 0.5);
        mr = static_cast<float>(n + kGap + (plane - 1) * (h + kGap) + z / s - 0.5);
      }
      map[u] = cv::Vec2f(mc, mr);
    }
  }
  return b;
}

double Scene::gain(int camera, int frame, double t_s) const {
  const double phase = 2 * M_PI * unit(hash3(camera, 0, static_cast<int>(seed_ & 0x7fffffff)));
  double g = 1 + options_.drift * std::sin(2 * M_PI * t_s / options_.drift_period_s + phase);
  if (options_.flicker > 0) {
    std::mt19937_64 rng(draw_seed(seed_, camera, frame, 101));
    g *= 1 + std::normal_distribution<double>(0, options_.flicker)(rng);
  }
  return g;
}

CameraRenderer::CameraRenderer(const Motion& motion, const BodyShape& body,
                               const CameraModel& camera, const Scene& scene, double fps)
    : motion_(motion),
      body_(body),
      scene_(scene),
      fps_(fps),
      view_(camera),
      backdrop_(scene.backdrop(view_)) {
  HULLPOSE_THROW_UNLESS(fps > 0, "frame rate must be positive");
  noise_.create(camera.height + kNoiseMargin, camera.width + kNoiseMargin, CV_16SC3);
  cv::RNG rng(draw_seed(scene.seed(), camera.id, -1, 102));
  rng.fill(noise_, cv::RNG::NORMAL, 0,
           scene.options().noise_sigma / static_cast<double>(kNoiseScale));
}

void CameraRenderer::render(int frame, cv::Mat& bgr, cv::Mat& mask) {
  const double t = frame / fps_;
  motion_.sample(t, joints_);
  pose_avatar(body_, joints_, primitives_);
  scene_.shadows(primitives_, atlas_);
  render_posed(frame, t, primitives_, atlas_, bgr, mask);
}

void CameraRenderer::render_posed(int frame, double t_s, const std::vector<Primitive>& primitives,
                                  const cv::Mat& shadow_atlas, cv::Mat& bgr, cv::Mat& mask) {
  view_.render_layers(primitives, mask, material_, facing_);
  cv::remap(shadow_atlas, shadow_, backdrop_.shadow_map, cv::noArray(), cv::INTER_LINEAR,
            cv::BORDER_CONSTANT, 0);
  compose(frame, t_s, true, bgr);
}

void CameraRenderer::render_background(int index, cv::Mat& bgr) {
  const auto& c = camera();
  shadow_.create(c.height, c.width, CV_32FC1);
  shadow_.setTo(0);
  material_.create(c.height, c.width, CV_8UC1);
  material_.setTo(255);
  compose(-1 - index, -static_cast<double>(index), false, bgr);
}

void CameraRenderer::render_dark(int frame, cv::Mat& bgr) {
  const auto& c = camera();
  std::mt19937_64 rng(draw_seed(scene_.seed(), c.id, frame, 103));
  // Saturates: black plus the positive half of the noise.
  noise_(noise_window_at(rng, c.width, c.height))
      .convertTo(bgr, CV_8UC3, static_cast<double>(kNoiseScale));
}

void CameraRenderer::compose(int frame, double t_s, bool person, cv::Mat& bgr) {
  const auto& c = camera();
  const float gain = static_cast<float>(scene_.gain(c.id, frame, t_s));
  const float strength = static_cast<float>(scene_.options().shadow_strength);
  // Sensor noise: a window of the camera's noise bank at a random offset per frame (drawing
  // 1.4 M normal deviates per frame would cost more than the rest of the frame).
  std::mt19937_64 rng(draw_seed(scene_.seed(), c.id, frame, 102));
  const cv::Mat noise_window = noise_(noise_window_at(rng, c.width, c.height));
  bgr.create(c.height, c.width, CV_8UC3);
  std::array<cv::Vec3f, kNumMaterials> palette;
  for (int m = 0; m < kNumMaterials; ++m)
    palette[static_cast<size_t>(m)] = scene_.colour(static_cast<Material>(m));
  for (int v = 0; v < c.height; ++v) {
    const auto* base = backdrop_.colour.ptr<cv::Vec3f>(v);
    const auto* shadow = shadow_.ptr<float>(v);
    const auto* material = material_.ptr<uint8_t>(v);
    const float* facing = person ? facing_.ptr<float>(v) : nullptr;
    const auto* noise = noise_window.ptr<cv::Vec3s>(v);
    auto* out = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < c.width; ++u) {
      cv::Vec3f px;
      if (material[u] != 255)
        px = palette[material[u]] * (0.35f + 0.65f * facing[u]);
      else
        px = base[u] * (1.f - strength * shadow[u]);
      px = px * gain + cv::Vec3f(noise[u][0], noise[u][1], noise[u][2]) * kNoiseScale;
      out[u] = cv::Vec3b(cv::saturate_cast<uint8_t>(px[0]), cv::saturate_cast<uint8_t>(px[1]),
                         cv::saturate_cast<uint8_t>(px[2]));
    }
  }
}

}  // namespace hullpose::synth
