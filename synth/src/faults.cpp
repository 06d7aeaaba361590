#include "hullpose/synth/faults.hpp"

#include <Eigen/Geometry>
#include <charconv>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>

#include "hullpose/common/check.hpp"

namespace hullpose::synth {
namespace {

enum Kind : int { kCalibration = 1, kJitter, kDrop, kSalt, kPepper, kBlobs, kHoles };

uint64_t splitmix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

double number(std::string_view key, std::string_view text) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  HULLPOSE_THROW_UNLESS(
      ec == std::errc() && end == text.data() + text.size() && std::isfinite(v) && v >= 0,
      "--noise: " << key << "='" << text << "' must be a non-negative number");
  return v;
}

// An ellipse's axes and angle, drawn in the order x86-64 GCC evaluated them when they were
// one call's arguments (right to left: angle, height, width), so seeded datasets stay as they
// were and are the same on every architecture (argument order is unspecified in C++).
struct Ellipse {
  cv::Size axes;
  double angle_deg;
};
Ellipse random_ellipse(std::mt19937_64& rng, std::uniform_real_distribution<double>& size,
                       std::uniform_real_distribution<double>& angle) {
  const double angle_deg = angle(rng);
  const int height = cvRound(size(rng));
  const int width = cvRound(size(rng));
  return {cv::Size(width, height), angle_deg};
}

// Positions inside `box` drawn uniformly.
cv::Point random_point(std::mt19937_64& rng, const cv::Rect& box) {
  std::uniform_int_distribution<int> ux(box.x, box.x + box.width - 1),
      uy(box.y, box.y + box.height - 1);
  return {ux(rng), uy(rng)};
}

}  // namespace

bool FaultSpec::any() const {
  return silhouette_noise() || calib_px > 0 || calib_deg > 0 || jitter_ms > 0 || drop > 0 ||
         dark_camera >= 0;
}

FaultSpec FaultSpec::parse(std::string_view spec) {
  FaultSpec f;
  if (spec.empty() || spec == "none") return f;
  size_t start = 0;
  while (start <= spec.size()) {
    const size_t comma = spec.find(',', start);
    const std::string_view item = spec.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    const size_t eq = item.find('=');
    HULLPOSE_THROW_UNLESS(eq != std::string_view::npos,
                          "--noise: '" << item << "' is not key=value");
    const std::string_view key = item.substr(0, eq), value = item.substr(eq + 1);
    auto prob = [&](double& field) {
      field = number(key, value);
      HULLPOSE_THROW_UNLESS(field <= 1, "--noise: " << key << " is a probability, got " << value);
    };
    if (key == "salt")
      prob(f.salt);
    else if (key == "pepper")
      prob(f.pepper);
    else if (key == "drop")
      prob(f.drop);
    else if (key == "blobs")
      f.blobs = number(key, value);
    else if (key == "holes")
      f.holes = number(key, value);
    else if (key == "blob_px")
      f.blob_px = number(key, value);
    else if (key == "calib_px")
      f.calib_px = number(key, value);
    else if (key == "calib_deg")
      f.calib_deg = number(key, value);
    else if (key == "jitter_ms")
      f.jitter_ms = number(key, value);
    else if (key == "dark") {
      const size_t at = value.find('@');
      f.dark_camera = static_cast<int>(number(key, value.substr(0, at)));
      f.dark_from =
          at == std::string_view::npos ? 0 : static_cast<int>(number(key, value.substr(at + 1)));
    } else {
      HULLPOSE_THROW("--noise: unknown key '"
                     << key
                     << "' (salt, pepper, blobs, holes, blob_px, calib_px, calib_deg, "
                        "jitter_ms, drop, dark=CAM[@FRAME])");
    }
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  HULLPOSE_THROW_UNLESS(f.blob_px >= 1 && f.blob_px <= 200, "--noise: blob_px must be in 1..200");
  HULLPOSE_THROW_UNLESS(f.blobs <= 100 && f.holes <= 100,
                        "--noise: at most 100 blobs and holes per mask");
  return f;
}

std::string FaultSpec::describe() const {
  std::ostringstream s;
  auto put = [&](const char* key, double v) {
    if (v > 0) s << (s.tellp() > 0 ? "," : "") << key << "=" << v;
  };
  put("salt", salt);
  put("pepper", pepper);
  put("blobs", blobs);
  put("holes", holes);
  if (blobs > 0 || holes > 0) put("blob_px", blob_px);
  put("calib_px", calib_px);
  put("calib_deg", calib_deg);
  put("jitter_ms", jitter_ms);
  put("drop", drop);
  if (dark_camera >= 0)
    s << (s.tellp() > 0 ? "," : "") << "dark=" << dark_camera << "@" << dark_from;
  return s.str();
}

uint64_t draw_seed(uint64_t seed, int camera, int frame, int kind) {
  return splitmix(
      splitmix(splitmix(seed) ^ static_cast<uint64_t>(camera + 1)) ^
      (static_cast<uint64_t>(static_cast<uint32_t>(frame)) << 8 | static_cast<uint64_t>(kind)));
}

Rig perturb_calibration(const Rig& rig, const FaultSpec& spec, uint64_t seed) {
  Rig out = rig;
  if (spec.calib_px <= 0 && spec.calib_deg <= 0) return out;
  for (auto& c : out.cameras) {
    std::mt19937_64 rng(draw_seed(seed, c.id, -1, kCalibration));
    std::normal_distribution<double> px(0, spec.calib_px), deg(0, spec.calib_deg);
    c.cx += px(rng);
    c.cy += px(rng);
    // One draw per statement: argument order is unspecified. Last axis first keeps the
    // datasets x86-64 GCC (right to left) rendered before.
    const double az = deg(rng), ay = deg(rng), ax = deg(rng);
    const Eigen::Vector3d axis(ax, ay, az);
    if (axis.norm() > 0) {
      // Rotate the camera about its own centre: the centre stays, the orientation errs.
      const Eigen::Vector3d centre = c.centre();
      c.R = Eigen::AngleAxisd(axis.norm() * M_PI / 180, axis.normalized()).toRotationMatrix() * c.R;
      c.t = -c.R * centre;
    }
  }
  return out;
}

double trigger_offset_s(const FaultSpec& spec, uint64_t seed, int camera, int frame) {
  if (spec.jitter_ms <= 0) return 0;
  std::mt19937_64 rng(draw_seed(seed, camera, frame, kJitter));
  return std::normal_distribution<double>(0, spec.jitter_ms * 1e-3)(rng);
}

bool frame_dropped(const FaultSpec& spec, uint64_t seed, int camera, int frame) {
  if (spec.drop <= 0) return false;
  std::mt19937_64 rng(draw_seed(seed, camera, frame, kDrop));
  return std::uniform_real_distribution<double>(0, 1)(rng) < spec.drop;
}

void corrupt_silhouette(cv::Mat& mask, const FaultSpec& spec, uint64_t seed, int camera,
                        int frame) {
  HULLPOSE_ASSERT(mask.type() == CV_8UC1);
  const cv::Rect image(0, 0, mask.cols, mask.rows);
  const cv::Rect person = cv::boundingRect(mask);
  if (spec.holes > 0 && !person.empty()) {
    std::mt19937_64 rng(draw_seed(seed, camera, frame, kHoles));
    const int n = std::poisson_distribution<int>(spec.holes)(rng);
    std::uniform_real_distribution<double> size(0.5 * spec.blob_px, 1.5 * spec.blob_px),
        angle(0, 180);
    for (int i = 0; i < n; ++i) {
      for (int tries = 0; tries < 64; ++tries) {  // a hole starts inside the silhouette
        const cv::Point p = random_point(rng, person);
        if (mask.at<uint8_t>(p) == 0) continue;
        const Ellipse e = random_ellipse(rng, size, angle);
        cv::ellipse(mask, p, e.axes, e.angle_deg, 0, 360, 0, cv::FILLED);
        break;
      }
    }
  }
  if (spec.blobs > 0) {
    std::mt19937_64 rng(draw_seed(seed, camera, frame, kBlobs));
    const int n = std::poisson_distribution<int>(spec.blobs)(rng);
    std::uniform_real_distribution<double> size(0.5 * spec.blob_px, 1.5 * spec.blob_px),
        angle(0, 180);
    // Spurious blobs near the person (shadows, reflections), anywhere if there is none.
    const cv::Rect area =
        person.empty() ? image : (person + cv::Size(160, 160) - cv::Point(80, 80)) & image;
    for (int i = 0; i < n; ++i) {
      const Ellipse e = random_ellipse(rng, size, angle);
      cv::ellipse(mask, random_point(rng, area), e.axes, e.angle_deg, 0, 360, 255, cv::FILLED);
    }
  }
  if (spec.pepper > 0 && !person.empty()) {
    std::mt19937_64 rng(draw_seed(seed, camera, frame, kPepper));
    const int n = std::binomial_distribution<int>(person.area(), spec.pepper)(rng);
    for (int i = 0; i < n; ++i) mask.at<uint8_t>(random_point(rng, person)) = 0;
  }
  if (spec.salt > 0) {
    std::mt19937_64 rng(draw_seed(seed, camera, frame, kSalt));
    const int n = std::binomial_distribution<int>(image.area(), spec.salt)(rng);
    for (int i = 0; i < n; ++i) mask.at<uint8_t>(random_point(rng, image)) = 255;
  }
}

}  // namespace hullpose::synth
