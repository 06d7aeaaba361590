#include "hullpose/eval/consistency_report.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "hullpose/common/check.hpp"

namespace hullpose::eval {
namespace {

// NaN (nothing to average) as null.
nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::string fixed(double v, int decimals = 1) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

cv::Scalar side_colour(Joint j) {
  const std::string_view n = kJointNames[static_cast<size_t>(index(j))];
  if (n[0] == 'L' && n != "LBack") return {255, 120, 40};  // BGR: blue
  if (n[0] == 'R') return {60, 60, 230};                   // red
  return {80, 200, 80};                                    // green
}

}  // namespace

void write_consistency_json(std::ostream& out, const ConsistencyResult& r) {
  nlohmann::json j;
  j["mode"] = "consistency";
  j["frames"] = r.frames;
  j["estimates"] = r.estimates;
  j["valid"] = r.valid;
  j["valid_pct"] = number(r.valid_pct);
  j["scored_frames"] = r.scored_frames;
  j["bone_points"] = r.points;
  j["inside_all_views_pct"] = number(r.inside_all_pct);
  j["frames_inside_n_minus_1_pct"] = number(r.frames_n_minus_1_pct);
  for (const CameraAgreement& c : r.cameras)
    j["inside_pct_per_camera"][std::to_string(c.camera_id)] = number(c.inside_pct);
  j["bone_length_cv_mean"] = number(r.bone_cv_mean);
  for (int b = 0; b < kNumBones; ++b) {
    j["bone_length_cv"][bone_key(b)] = number(r.bone_cv[static_cast<size_t>(b)]);
    j["bone_inside_all_views_pct"][bone_key(b)] =
        number(r.bone_inside_all_pct[static_cast<size_t>(b)]);
  }
  j["jitter_mean_mm"] = number(r.jitter_mean_mm);
  for (size_t i = 0; i < kNumJoints; ++i) {
    j["jitter_mm"][std::string(kJointNames[i])] = number(r.jitter_mm[i]);
    j["speed_mm_per_frame"][std::string(kJointNames[i])] = number(r.speed_mm[i]);
  }
  out << j.dump() << '\n';
}

void write_consistency_table(std::ostream& out, const ConsistencyResult& r,
                             const std::string& dataset, const std::string& estimate) {
  out << "hullpose-eval: " << estimate << " against the silhouettes of " << dataset
      << " (no ground truth)\n"
      << "  valid                          " << fixed(r.valid_pct) << " % (" << r.valid << " of "
      << r.frames << " frames, " << r.estimates << " estimates)\n"
      << "  bone points inside every view  " << fixed(r.inside_all_pct) << " % (" << r.points
      << " points, " << r.scored_frames << " frames)\n"
      << "  frames inside >= n-1 views     " << fixed(r.frames_n_minus_1_pct) << " %\n"
      << "  bone length CV (mean)          " << fixed(100 * r.bone_cv_mean, 2) << " %\n"
      << "  jitter (mean |2nd difference|) " << fixed(r.jitter_mean_mm) << " mm\n"
      << "  per camera: inside %\n";
  for (const CameraAgreement& c : r.cameras)
    out << "    camera " << std::setw(2) << c.camera_id << "  " << std::setw(6)
        << fixed(c.inside_pct) << " % (" << c.frames << " frames)\n";
  out << "  per bone: inside every view %, length CV %\n";
  for (int b = 0; b < kNumBones; ++b)
    out << "    " << std::left << std::setw(12) << bone_key(b) << std::right << std::setw(8)
        << fixed(r.bone_inside_all_pct[static_cast<size_t>(b)]) << std::setw(8)
        << fixed(100 * r.bone_cv[static_cast<size_t>(b)], 2) << '\n';
  out << "  per joint: speed mm/frame, jitter mm\n";
  for (size_t i = 0; i < kNumJoints; ++i)
    out << "    " << std::left << std::setw(8) << kJointNames[i] << std::right << std::setw(8)
        << fixed(r.speed_mm[i]) << std::setw(8) << fixed(r.jitter_mm[i]) << '\n';
}

cv::Mat draw_view(const CameraModel& camera, const cv::Mat& mask, const cv::Mat& colour,
                  const JointPositions& joints, double tolerance_px, double sample_step_mm) {
  cv::Mat img;
  if (!colour.empty()) {
    img = colour.clone();
  } else {
    img = cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar::all(0));
    if (!mask.empty()) img.setTo(cv::Scalar::all(110), mask);
  }
  cv::Mat near;  // foreground within the tolerance, as the score reads it
  if (!mask.empty()) {
    std::vector<std::vector<cv::Point>> outline;
    cv::findContours(mask.clone(), outline, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(img, outline, -1, cv::Scalar(255, 255, 0), 1, cv::LINE_AA);
    const int r = static_cast<int>(std::ceil(tolerance_px));
    if (r > 0)
      cv::dilate(mask, near,
                 cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
    else
      near = mask;
  }
  const int thick = std::max(2, camera.width / 400);
  auto pixel = [&](const Eigen::Vector3d& p) -> std::optional<cv::Point> {
    const auto px = camera.project(p);
    if (!px) return std::nullopt;
    return cv::Point(static_cast<int>(std::lround(px->x())),
                     static_cast<int>(std::lround(px->y())));
  };
  for (const Bone& b : kBones) {
    const auto a = pixel(joints[static_cast<size_t>(index(b.parent))]);
    const auto c = pixel(joints[static_cast<size_t>(index(b.child))]);
    if (a && c) cv::line(img, *a, *c, side_colour(b.child), thick, cv::LINE_AA);
  }
  for (const Eigen::Vector3d& p : bone_points(joints, sample_step_mm)) {
    const auto q = pixel(p);
    if (!q || near.empty()) continue;
    const bool in =
        q->x >= 0 && q->y >= 0 && q->x < near.cols && q->y < near.rows && near.at<uint8_t>(*q) != 0;
    if (!in) cv::circle(img, *q, thick + 1, cv::Scalar(0, 230, 255), cv::FILLED, cv::LINE_AA);
  }
  return img;
}

std::filesystem::path write_consistency_report(const std::filesystem::path& dir,
                                               const std::filesystem::path& dataset,
                                               const std::string& estimate,
                                               const std::vector<PoseRecord>& estimates,
                                               const ConsistencyResult& r,
                                               const ConsistencyOptions& o) {
  std::filesystem::create_directories(dir);
  const DatasetPaths paths(dataset);
  const Rig rig = load_rig(paths.rig());
  std::ostringstream html;
  html
      << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>hullpose-eval: " << estimate
      << "</title><style>body{font-family:sans-serif;margin:24px;background:#f8fafc;color:#0f172a}"
         ".cards{display:flex;gap:12px;flex-wrap:wrap}.card{background:#fff;border:1px solid "
         "#cbd5e1;"
         "border-radius:6px;padding:10px 14px}.card "
         "b{display:block;font-size:22px}table{border-collapse:"
         "collapse;background:#fff}td,th{border:1px solid #cbd5e1;padding:3px 8px;text-align:right}"
         "figure{display:inline-block;margin:4px}img{max-width:420px;border:1px solid #94a3b8}"
         "figcaption{font-size:12px}</style></head><body>\n"
      << "<h1>Consistency without ground truth</h1><p>Estimate <code>" << estimate
      << "</code> against the "
      << "silhouettes of <code>" << dataset.string() << "</code> (" << rig.cameras.size()
      << " cameras, tolerance " << o.tolerance_px << " px, a point every " << o.sample_step_mm
      << " mm along the bones).</p>\n<div class=\"cards\">"
      << "<div class=\"card\">valid<b>" << fixed(r.valid_pct) << " %</b></div>"
      << "<div class=\"card\">bone points inside every view<b>" << fixed(r.inside_all_pct)
      << " %</b></div>"
      << "<div class=\"card\">frames inside &ge; n&minus;1 views<b>"
      << fixed(r.frames_n_minus_1_pct) << " %</b></div>"
      << "<div class=\"card\">bone length CV<b>" << fixed(100 * r.bone_cv_mean, 2) << " %</b></div>"
      << "<div class=\"card\">jitter<b>" << fixed(r.jitter_mean_mm) << " mm</b></div></div>\n";
  html << "<h2>Per camera</h2><table><tr><th>camera</th><th>inside %</th><th>frames with a "
          "mask</th></tr>";
  for (const CameraAgreement& c : r.cameras)
    html << "<tr><td>" << c.camera_id << "</td><td>" << fixed(c.inside_pct) << "</td><td>"
         << c.frames << "</td></tr>";
  html << "</table>\n<h2>Per joint</h2><table><tr><th>joint</th><th>speed mm/frame</th><th>jitter "
          "mm</th></tr>";
  for (size_t i = 0; i < kNumJoints; ++i)
    html << "<tr><td>" << kJointNames[i] << "</td><td>" << fixed(r.speed_mm[i]) << "</td><td>"
         << fixed(r.jitter_mm[i]) << "</td></tr>";
  html << "</table>\n<h2>Frames</h2><p>Bones: left blue, right red, centre green; yellow dots: "
          "bone points outside "
          "the silhouette (cyan outline).</p>\n";
  for (int f : r.picture_frames) {
    const auto e = std::find_if(estimates.begin(), estimates.end(),
                                [&](const PoseRecord& p) { return p.frame == f; });
    if (e == estimates.end()) continue;
    html << "<h3>frame " << f << (e->valid ? "" : " (invalid)") << "</h3>\n";
    for (const CameraModel& cam : rig.cameras) {
      const cv::Mat mask = cv::imread(paths.mask(cam.id, f).string(), cv::IMREAD_GRAYSCALE);
      // Imported silhouette-only captures have no colour frames; imread would warn on each.
      const std::filesystem::path rgb = paths.rgb(cam.id, f);
      const cv::Mat colour =
          std::filesystem::exists(rgb) ? cv::imread(rgb.string(), cv::IMREAD_COLOR) : cv::Mat();
      const bool fits = [&](const cv::Mat& m) {
        return m.empty() || (m.cols == cam.width && m.rows == cam.height);
      }(mask);
      const cv::Mat view =
          draw_view(cam, fits ? mask : cv::Mat(),
                    colour.size() == cv::Size(cam.width, cam.height) ? colour : cv::Mat(),
                    e->joints, o.tolerance_px, o.sample_step_mm);
      // Cropped to the person (the silhouette and the skeleton) with a margin: the page shows them.
      cv::Rect box = fits && !mask.empty() ? cv::boundingRect(mask) : cv::Rect();
      for (const Eigen::Vector3d& p : e->joints)
        if (const auto px = cam.project(p))
          box |= cv::Rect(static_cast<int>(px->x()), static_cast<int>(px->y()), 1, 1);
      const int margin = std::max(box.width, box.height) / 8 + 8;
      box = cv::Rect(box.x - margin, box.y - margin, box.width + 2 * margin,
                     box.height + 2 * margin) &
            cv::Rect(0, 0, view.cols, view.rows);
      const std::string name =
          "frame" + std::to_string(f) + "_cam" + std::to_string(cam.id) + ".png";
      HULLPOSE_THROW_UNLESS(cv::imwrite((dir / name).string(), box.area() > 0 ? view(box) : view),
                            (dir / name).string() << ": cannot write");
      html << "<figure><img src=\"" << name << "\" alt=\"frame " << f << " camera " << cam.id
           << "\"><figcaption>camera " << cam.id << (mask.empty() ? " (no mask)" : "")
           << "</figcaption></figure>\n";
    }
  }
  html << "</body></html>\n";
  const std::filesystem::path page = dir / "report.html";
  std::ofstream out(page);
  out << html.str();
  HULLPOSE_THROW_UNLESS(out, page.string() << ": cannot write");
  return page;
}

}  // namespace hullpose::eval
