// The fusion core on CMU 55_01 rendered with the thesis rig (8 cameras, 800x600): carving equals
// the brute-force reference, clean-up leaves one person, every skeletoniser preserves topology.
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/thin/topology_stats.hpp"
#include "support/cmu_scene.hpp"

using namespace hullpose;
namespace ft = hullpose::fusion::testing;

TEST_CASE("CMU 55_01: carving equals brute force, skeletons keep the hull's topology") {
  const ft::CmuFrames cmu = ft::render_cmu_55_01(4);
  REQUIRE(cmu.rig.cameras.size() == 8);
  for (int res : {64, 128}) {
    carve::Carver carver(cmu.rig, {res, 0, 2});
    for (size_t f = 0; f < cmu.views.size(); ++f) {
      INFO("resolution " << res << " frame " << cmu.frames[f]);
      fusion::BitGrid fast, boxed, brute;
      carve::CarveReport report;
      carver.carve(cmu.views[f], fast, report);
      // With the foreground boxes the fusion host passes (the silhouette codec's ROI), as benched.
      std::vector<PixelRoi> boxes;
      for (const cv::Mat& v : cmu.views[f]) {
        const cv::Rect r = cv::boundingRect(v);
        boxes.push_back({r.x, r.y, r.width, r.height});
      }
      carver.carve(cmu.views[f], boxed, report, boxes);
      carver.carve_brute_force(cmu.views[f], brute, report);
      CHECK(report.voxels > 300);
      CHECK(fast == brute);
      CHECK(boxed == brute);
    }
    for (auto sk : {fusion::Skeletoniser::kCk3, fusion::Skeletoniser::kD6i1d})
      for (auto rule :
           {thin::CurveRule::kCk3, thin::CurveRule::kIsthmus, thin::CurveRule::kEndVoxel}) {
        if (sk == fusion::Skeletoniser::kD6i1d && rule != thin::CurveRule::kCk3) continue;
        fusion::FusionOptions opt;
        opt.resolution = res;
        opt.skeletoniser = sk;
        opt.curve_rule = rule;
        fusion::FusionCore core(cmu.rig, opt);
        for (size_t f = 0; f < cmu.views.size(); ++f) {
          INFO("resolution " << res << " frame " << cmu.frames[f] << " rule "
                             << thin::to_string(rule));
          const auto& r = core.process(cmu.views[f]);
          REQUIRE(r.valid);
          CHECK(thin::topology_invariants(r.hull).components == 1);
          CHECK(thin::topology_invariants(r.skeleton) == thin::topology_invariants(r.hull));
          // At 64³ this volume has 53 mm voxels: limbs are 1-2 voxels thick and the skeleton is
          // a large part of the hull; at 128³ it is a small one.
          if (res == 128) CHECK(r.skeleton_voxels.size() * 5 < r.hull_stats.voxels);
        }
      }
  }
}
