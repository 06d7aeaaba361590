#include "hullpose/eval/consistency.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose::eval {

HULLPOSE_LOG_CATEGORY(Consistency, "eval")

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double pct(size_t part, size_t whole) {
  return whole == 0 ? kNaN : 100.0 * static_cast<double>(part) / static_cast<double>(whole);
}

const Eigen::Vector3d& at(const JointPositions& p, Joint j) {
  return p[static_cast<size_t>(index(j))];
}

// The masks of one frame, dilated by the tolerance: "foreground within tolerance_px" is one read.
struct FrameMasks {
  std::vector<cv::Mat> masks;  // per rig camera; empty = no mask
  void load(const DatasetPaths& paths, const Rig& rig, int frame, const cv::Mat& kernel) {
    masks.resize(rig.cameras.size());
    for (size_t c = 0; c < rig.cameras.size(); ++c) {
      const CameraModel& cam = rig.cameras[c];
      const std::filesystem::path file = paths.mask(cam.id, frame);
      masks[c].release();
      if (!std::filesystem::exists(file)) continue;
      cv::Mat m = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
      if (m.empty() || m.cols != cam.width || m.rows != cam.height) {
        HULLPOSE_LOG(Consistency, Warn)
            << file.string() << ": unreadable or of the wrong size: camera " << cam.id
            << " left out of frame " << frame;
        continue;
      }
      if (kernel.empty())
        masks[c] = m;
      else
        cv::dilate(m, masks[c], kernel);
    }
  }
};

bool inside(const CameraModel& cam, const cv::Mat& mask, const Eigen::Vector3d& p) {
  const auto px = cam.project(p);
  if (!px) return false;
  const int x = static_cast<int>(std::lround(px->x())), y = static_cast<int>(std::lround(px->y()));
  return x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<uint8_t>(y, x) != 0;
}

}  // namespace

std::vector<Eigen::Vector3d> bone_points(const JointPositions& joints, double step_mm,
                                         std::vector<int>* bone_of) {
  std::vector<Eigen::Vector3d> out;
  if (bone_of != nullptr) bone_of->clear();
  for (int bone = 0; bone < kNumBones; ++bone) {
    const Bone& b = kBones[static_cast<size_t>(bone)];
    const Eigen::Vector3d& a = at(joints, b.parent);
    const Eigen::Vector3d& c = at(joints, b.child);
    const int n = std::max(1, static_cast<int>(std::ceil((c - a).norm() / step_mm)));
    for (int i = 0; i <= n; ++i) out.push_back(a + (c - a) * (static_cast<double>(i) / n));
    if (bone_of != nullptr) bone_of->insert(bone_of->end(), static_cast<size_t>(n) + 1, bone);
  }
  return out;
}

std::string bone_key(int bone) {
  const Bone& b = kBones[static_cast<size_t>(bone)];
  return std::string(kJointNames[static_cast<size_t>(index(b.parent))]) + "-" +
         std::string(kJointNames[static_cast<size_t>(index(b.child))]);
}

ConsistencyResult evaluate_consistency(const std::filesystem::path& dataset,
                                       const std::vector<PoseRecord>& estimates,
                                       const ConsistencyOptions& o) {
  HULLPOSE_THROW_UNLESS(o.tolerance_px >= 0 && o.sample_step_mm > 0,
                        "consistency: tolerance must be >= 0 and the sample step > 0");
  const DatasetPaths paths(dataset);
  const Rig rig = load_rig(paths.rig());
  const DatasetMeta meta = read_meta(paths.meta());
  ConsistencyResult r;
  r.frames = meta.frames;
  r.estimates = static_cast<int>(estimates.size());
  const int radius = static_cast<int>(std::ceil(o.tolerance_px));
  const cv::Mat kernel =
      radius > 0
          ? cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1))
          : cv::Mat();

  const size_t ncam = rig.cameras.size();
  std::vector<size_t> cam_points(ncam, 0), cam_inside(ncam, 0);
  std::vector<int> cam_frames(ncam, 0);
  size_t inside_all = 0;
  std::array<size_t, kNumBones> bone_n{}, bone_inside{};
  std::vector<int> bone_of;
  int frames_ok = 0;
  FrameMasks fm;
  std::vector<std::vector<double>> lengths(kNumBones);
  std::map<int, const PoseRecord*> valid;
  for (const PoseRecord& e : estimates) {
    if (!e.valid || e.frame < 0 || e.frame >= meta.frames) continue;
    valid[e.frame] = &e;
    ++r.valid;
    for (size_t b = 0; b < kBones.size(); ++b)
      lengths[b].push_back((at(e.joints, kBones[b].child) - at(e.joints, kBones[b].parent)).norm());
    fm.load(paths, rig, e.frame, kernel);
    const std::vector<Eigen::Vector3d> pts = bone_points(e.joints, o.sample_step_mm, &bone_of);
    int present = 0;
    for (size_t c = 0; c < ncam; ++c) present += !fm.masks[c].empty();
    if (present == 0) continue;
    ++r.scored_frames;
    bool frame_ok = true;
    size_t frame_inside = 0;
    for (size_t c = 0; c < ncam; ++c) cam_frames[c] += !fm.masks[c].empty();
    for (size_t k = 0; k < pts.size(); ++k) {
      const Eigen::Vector3d& p = pts[k];
      int in = 0;
      for (size_t c = 0; c < ncam; ++c) {
        if (fm.masks[c].empty()) continue;
        const bool hit = inside(rig.cameras[c], fm.masks[c], p);
        ++cam_points[c];
        cam_inside[c] += hit;
        in += hit;
      }
      frame_inside += in == present;
      ++bone_n[static_cast<size_t>(bone_of[k])];
      bone_inside[static_cast<size_t>(bone_of[k])] += in == present;
      frame_ok = frame_ok && in >= present - 1;
    }
    inside_all += frame_inside;
    r.points += pts.size();
    frames_ok += frame_ok;
    r.frame_inside_pct_frames.push_back(e.frame);
    r.frame_inside_pct.push_back(pct(frame_inside, pts.size()));
  }
  r.valid_pct = meta.frames > 0 ? 100.0 * r.valid / meta.frames : kNaN;
  r.inside_all_pct = pct(inside_all, r.points);
  r.frames_n_minus_1_pct =
      pct(static_cast<size_t>(frames_ok), static_cast<size_t>(r.scored_frames));
  for (size_t b = 0; b < kBones.size(); ++b)
    r.bone_inside_all_pct[b] = pct(bone_inside[b], bone_n[b]);
  for (size_t c = 0; c < ncam; ++c)
    r.cameras.push_back(
        {rig.cameras[c].id, cam_points[c], pct(cam_inside[c], cam_points[c]), cam_frames[c]});

  double cv_sum = 0;
  int cv_n = 0;
  for (size_t b = 0; b < kBones.size(); ++b) {
    const std::vector<double>& l = lengths[b];
    if (l.size() < 2) {
      r.bone_cv[b] = kNaN;
      continue;
    }
    double mean = 0, var = 0;
    for (double v : l) mean += v;
    mean /= static_cast<double>(l.size());
    for (double v : l) var += (v - mean) * (v - mean);
    var /= static_cast<double>(l.size());
    r.bone_cv[b] = mean > 0 ? std::sqrt(var) / mean : kNaN;
    cv_sum += r.bone_cv[b];
    ++cv_n;
  }
  r.bone_cv_mean = cv_n > 0 ? cv_sum / cv_n : kNaN;

  std::array<double, kNumJoints> speed{}, jitter{};
  int nspeed = 0, njitter = 0;
  for (const auto& [f, e] : valid) {
    const auto prev = valid.find(f - 1), next = valid.find(f + 1);
    if (prev == valid.end()) continue;
    ++nspeed;
    for (size_t j = 0; j < kNumJoints; ++j)
      speed[j] += (e->joints[j] - prev->second->joints[j]).norm();
    if (next == valid.end()) continue;
    ++njitter;
    for (size_t j = 0; j < kNumJoints; ++j)
      jitter[j] += (next->second->joints[j] - 2 * e->joints[j] + prev->second->joints[j]).norm();
  }
  double jsum = 0;
  for (size_t j = 0; j < kNumJoints; ++j) {
    r.speed_mm[j] = nspeed > 0 ? speed[j] / nspeed : kNaN;
    r.jitter_mm[j] = njitter > 0 ? jitter[j] / njitter : kNaN;
    jsum += r.jitter_mm[j];
  }
  r.jitter_mean_mm = njitter > 0 ? jsum / kNumJoints : kNaN;

  if (!o.show_frames.empty()) {
    r.picture_frames = o.show_frames;
  } else if (!r.frame_inside_pct_frames.empty()) {
    const size_t n = r.frame_inside_pct_frames.size();
    const size_t count = std::min<size_t>(static_cast<size_t>(std::max(0, o.pictures)), n);
    for (size_t i = 0; i < count; ++i)
      r.picture_frames.push_back(r.frame_inside_pct_frames[(2 * i + 1) * n / (2 * count)]);
  }
  return r;
}

}  // namespace hullpose::eval
