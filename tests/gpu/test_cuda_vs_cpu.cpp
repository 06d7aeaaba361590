// make test-gpu: the CUDA backend against the CPU path, voxel for voxel, on synthetic datasets.
// Needs a CUDA device: without one it FAILS with the probe's reason (it must never pass
// silently on a machine that cannot run it). Label "gpu": not part of make test / test-asan.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/carve/carver.hpp"
#include "hullpose/gpu/backend.hpp"
#include "hullpose/gpu/cuda_fusion.hpp"
#include "hullpose/thin/thinning.hpp"
#include "support/cmu_scene.hpp"
#include "support/synthetic_scene.hpp"

using namespace hullpose;
using fusion::BitGrid;
namespace ft = hullpose::fusion::testing;

namespace {

void require_device() {
  const gpu::DeviceInfo device = gpu::probe_device();
  if (!device.available) FAIL("make test-gpu needs a CUDA device: " << device.reason);
}

// Carving (with and without foreground boxes) and CK3 with every rule on one frame's views.
void compare(const Rig& rig, const std::vector<cv::Mat>& views, int resolution, int tolerance) {
  carve::Carver carver(rig, {resolution, tolerance, 1});
  for (thin::CurveRule rule : {thin::CurveRule::kCk3, thin::CurveRule::kIsthmus,
                               thin::CurveRule::kEndVoxel, thin::CurveRule::kUltimate}) {
    INFO("resolution " << resolution << " k " << tolerance << " rule " << thin::to_string(rule));
    const thin::ThinOptions options{rule, thin::ZeroCliqueTest::kSpan3, 1, 0};
    gpu::CudaFusion cuda(carver, options);
    BitGrid cpu_hull, gpu_hull;
    carve::CarveReport cpu_report, gpu_report;
    carver.carve(views, cpu_hull, cpu_report);
    cuda.carve(views, gpu_hull, gpu_report);
    REQUIRE(cpu_hull.count() > 0);
    CHECK(gpu_hull == cpu_hull);
    CHECK(gpu_report.voxels == cpu_report.voxels);
    CHECK(gpu_report.missing_cameras == cpu_report.missing_cameras);
    CHECK(cuda.carve_times().kernels_ms >= 0);

    thin::Ck3Thinner cpu_thinner(options);
    BitGrid cpu_skel = cpu_hull, gpu_skel = cpu_hull;
    const thin::ThinStats cs = cpu_thinner.thin(cpu_skel);
    const thin::ThinStats gs = cuda.thin(gpu_skel);
    CHECK(gpu_skel == cpu_skel);
    CHECK(gs.iterations == cs.iterations);
    CHECK(gs.final_voxels == cs.final_voxels);
    CHECK(gs.constrained == cs.constrained);
    // Twice on the same buffers: nothing carried over between frames.
    BitGrid again = cpu_hull;
    cuda.thin(again);
    CHECK(again == cpu_skel);
  }
}

}  // namespace

TEST_CASE("CUDA carving and CK3 equal the CPU on synthetic scenes at 64³, 128³ and 256³") {
  require_device();
  const Rig rig = ft::thesis_like_rig(320, 240);
  for (int res : {64, 128, 256}) {
    compare(rig, ft::render_views(rig, ft::human_capsules(0.35, 0.7, {150, -80})), res, 0);
  }
  auto views = ft::render_views(rig, ft::human_capsules(0.8));
  views[2] = cv::Mat();                                 // a camera that sent nothing
  views[5] = cv::Mat::zeros(views[5].size(), CV_8UC1);  // a dark camera
  compare(rig, views, 64, 1);
}

TEST_CASE("CUDA equals the CPU on CMU 55_01 (thesis rig, 800x600), with foreground boxes") {
  require_device();
  const ft::CmuFrames cmu = ft::render_cmu_55_01(2);
  for (int res : {64, 128}) {
    carve::Carver carver(cmu.rig, {res, 0, 1});
    gpu::CudaFusion cuda(carver, {});
    for (const auto& views : cmu.views) {
      std::vector<PixelRoi> boxes;
      for (const cv::Mat& v : views) {
        const cv::Rect r = cv::boundingRect(v);
        boxes.push_back({r.x, r.y, r.width, r.height});
      }
      BitGrid a, b;
      carve::CarveReport ra, rb;
      carver.carve(views, a, ra, boxes);
      cuda.carve(views, b, rb, boxes);
      CHECK(a == b);
    }
  }
}
