#include "support/crane_scene.hpp"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/import/pattern.hpp"
#include "hullpose/import/rig_import.hpp"

namespace hullpose::fusion::testing {

CraneFrames load_crane(int count, CraneVolume volume) {
  const std::filesystem::path root =
      std::filesystem::path(HULLPOSE_SHARED_DIR) / "data/real/vlasic-crane";
  import::RigImportOptions o;
  o.kind = import::SourceKind::kProjection;
  o.pattern = (root / "calibration/camera{N}.P").string();
  o.width = 1600;
  o.height = 1200;
  o.world.mm_per_unit = 1000;
  o.world.up = Eigen::Vector3d::UnitY();
  o.rig_id = "crane";
  // The thesis rig's volume size where the cameras' axes meet (near the floor's origin): the
  // subject stays inside it in all 120 frames.
  if (volume == CraneVolume::kThesis) o.volume_size_mm = Eigen::Vector3d(2400, 2400, 2200);
  CraneFrames out;
  out.rig = import::import_rig(o).rig;
  for (int i = 0; i < count; ++i) {
    const int f = static_cast<int>((i + 0.5) * 120 / count);
    out.frames.push_back(f);
    auto& views = out.views.emplace_back();
    for (const CameraModel& c : out.rig.cameras) {
      const std::string file = import::expand(
          import::expand((root / "silhouettes/camera{N}_{FFFF}.png").string(), 'N', c.id), 'F', f);
      views.push_back(cv::imread(file, cv::IMREAD_GRAYSCALE));
      HULLPOSE_THROW_UNLESS(!views.back().empty(), file << ": cannot read");
    }
  }
  return out;
}

}  // namespace hullpose::fusion::testing
