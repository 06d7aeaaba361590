#include "hullpose/import/silhouette_import.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/dataset.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/import/pattern.hpp"

namespace hullpose::import {

HULLPOSE_LOG_CATEGORY(Import, "import")

SilhouetteImport import_silhouettes(const SilhouetteImportOptions& o) {
  HULLPOSE_THROW_UNLESS(o.fps > 0, "--fps must be positive, got " << o.fps);
  HULLPOSE_THROW_UNLESS(o.threshold >= 0 && o.threshold < 255,
                        "--threshold must be in 0..254, got " << o.threshold);
  const Rig rig = load_rig(o.rig);
  // Fail on a pattern without fields before writing anything.
  expand(expand(o.pattern, 'N', 0), 'F', 0);
  const DatasetPaths paths(o.out);
  std::filesystem::create_directories(o.out);
  save_rig(rig, paths.rig());
  for (const CameraModel& c : rig.cameras)
    std::filesystem::create_directories(paths.camera_dir(c.id));

  SilhouetteImport out;
  cv::Mat mask;
  for (int f = 0; o.frames < 0 || f < o.frames; ++f) {
    const int source_frame = o.first + f;
    int present = 0;
    for (const CameraModel& c : rig.cameras) {
      const std::filesystem::path file = expand(expand(o.pattern, 'N', c.id), 'F', source_frame);
      if (!std::filesystem::exists(file)) {
        ++out.missing;
        continue;
      }
      ++present;
      const cv::Mat image = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
      if (image.empty()) {
        ++out.unreadable;
        HULLPOSE_LOG(Import, Warn)
            << file.string() << ": unreadable (corrupt or truncated): camera " << c.id
            << " has no mask for frame " << f;
        continue;
      }
      HULLPOSE_THROW_UNLESS(image.cols == c.width && image.rows == c.height,
                            file.string() << ": " << image.cols << "x" << image.rows
                                          << " but camera " << c.id << " of " << o.rig.string()
                                          << " is " << c.width << "x" << c.height);
      cv::threshold(image, mask, o.threshold, 255, cv::THRESH_BINARY);
      HULLPOSE_THROW_UNLESS(cv::imwrite(paths.mask(c.id, f).string(), mask),
                            paths.mask(c.id, f).string() << ": cannot write");
      ++out.masks;
    }
    if (present == 0 && o.frames < 0) {
      out.missing -= static_cast<int>(rig.cameras.size());  // the frame after the last
      break;
    }
    out.frames = f + 1;
  }
  HULLPOSE_THROW_UNLESS(out.frames > 0, "no file matches '" << o.pattern << "' at frame " << o.first
                                                            << " for the cameras of "
                                                            << o.rig.string());
  DatasetMeta meta;
  meta.motion = o.motion;
  meta.frames = out.frames;
  meta.fps = o.fps;
  for (const CameraModel& c : rig.cameras) meta.camera_ids.push_back(c.id);
  meta.noise = "";
  write_meta(paths.meta(), meta);
  return out;
}

}  // namespace hullpose::import
