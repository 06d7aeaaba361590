// Writes the small rig of rig_fixtures.hpp as a rig file, and optionally recordings of
// sequence-coded masks for camera nodes to replay (seq_pattern.hpp): frame k of camera c,
// <dir of OUT.yaml>/cam<c>/seq_<kkkkkk>.png, carries sequence k.
//   write_test_rig OUT.yaml N W H [RIG_ID [FRAMES]]
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/tool.hpp"
#include "rig_fixtures.hpp"
#include "seq_pattern.hpp"

namespace {
int run(int argc, const char* const* argv) {
  HULLPOSE_THROW_UNLESS(argc >= 5, "usage: write_test_rig OUT.yaml N W H [RIG_ID [FRAMES]]");
  const auto number = [&](int i) {
    return static_cast<int>(hullpose::cli::parse_integer(argv[0], argv[i]));
  };
  const hullpose::Rig rig =
      hullpose::testing::make_rig(number(2), number(3), number(4), argc > 5 ? argv[5] : "rigA");
  hullpose::save_rig(rig, argv[1]);
  const int frames = argc > 6 ? number(6) : 0;
  const std::filesystem::path dir = std::filesystem::absolute(argv[1]).parent_path();
  for (const hullpose::CameraModel& cam : rig.cameras) {
    if (frames <= 0) break;
    const std::filesystem::path cam_dir = dir / ("cam" + std::to_string(cam.id));
    std::filesystem::create_directories(cam_dir);
    cv::Mat mask(cam.height, cam.width, CV_8UC1);
    for (int k = 0; k < frames; ++k) {
      hullpose::testing::draw_seq_mask(mask, k, cam.id);
      char name[32];
      std::snprintf(name, sizeof name, "seq_%06d.png", k);
      HULLPOSE_THROW_UNLESS(cv::imwrite((cam_dir / name).string(), mask),
                            "cannot write " << (cam_dir / name).string());
    }
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("write_test_rig", argc, argv, run);
}
