#include "hullpose/fusion/fusion_core.hpp"

#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/gpu/cuda_fusion.hpp"

namespace hullpose::fusion {

HULLPOSE_LOG_CATEGORY(Fusion, "fusion")

const char* to_string(FusionFailure failure) {
  switch (failure) {
    case FusionFailure::kNone:
      return "none";
    case FusionFailure::kTooFewViews:
      return "too_few_views";
    case FusionFailure::kEmptyHull:
      return "empty_hull";
  }
  return "?";
}

FusionCore::FusionCore(const Rig& rig, const FusionOptions& options, Counters* counters)
    : options_(options),
      counters_(counters),
      carver_(rig, {options.resolution, options.tolerance, options.threads}),
      backend_(gpu::resolve_backend(options.backend)),
      cleanup_(options.cleanup),
      ck3_({options.curve_rule, thin::ZeroCliqueTest::kSpan3, options.threads, 0}) {
  if (backend_ == gpu::Backend::kCuda)
    cuda_ = std::make_unique<gpu::CudaFusion>(carver_, ck3_.options());
  result_.grid = carver_.grid();
  result_.hull.reset(result_.grid.dims);
  result_.skeleton.reset(result_.grid.dims);
}

FusionCore::~FusionCore() = default;

template <class Step>
bool FusionCore::on_gpu(Step&& step) {
  if (!cuda_) return false;
  try {
    step();
    return true;
  } catch (const std::exception& e) {
    // A CUDA error mid-run (device lost, out of memory, a driver fault) must not end the live
    // service: this frame and every later one run on the CPU path, which gives the same voxels.
    HULLPOSE_LOG(Fusion, Error) << "CUDA backend failed (" << e.what()
                                << "); continuing on the CPU";
    if (counters_) counters_->add("fusion.cuda_error");
    cuda_.reset();
    backend_ = gpu::Backend::kCpu;
    return false;
  }
}

const FusionResult& FusionCore::process(std::span<const cv::Mat> views,
                                        std::span<const PixelRoi> fg_boxes) {
  FusionResult& r = result_;
  r.timings = {};
  r.thin = {};
  r.hull_stats = {};
  r.skeleton_voxels.clear();
  r.valid = false;
  r.failure = FusionFailure::kNone;
  const StageTimer total;

  StageTimer t;
  if (!on_gpu([&] { cuda_->carve(views, r.hull, r.carve, fg_boxes); }))
    carver_.carve(views, r.hull, r.carve, fg_boxes);
  r.timings.carve_ms = static_cast<double>(t.elapsed_us()) * 1e-3;
  if (counters_) {
    if (!r.carve.missing_cameras.empty())
      counters_->add("fusion.camera_missing", static_cast<int64_t>(r.carve.missing_cameras.size()));
    if (!r.carve.rejected_cameras.empty())
      counters_->add("fusion.mask_rejected", static_cast<int64_t>(r.carve.rejected_cameras.size()));
  }
  if (!r.carve.valid) {
    r.failure = FusionFailure::kTooFewViews;
  } else if (r.carve.voxels == 0) {
    r.failure = FusionFailure::kEmptyHull;
  }
  if (r.failure != FusionFailure::kNone) {
    if (counters_)
      counters_->add(r.failure == FusionFailure::kTooFewViews ? "fusion.too_few_views"
                                                              : "fusion.empty_hull");
    HULLPOSE_LOG(Fusion, Debug) << "frame dropped: " << to_string(r.failure) << " ("
                                << r.carve.cameras_used << " cameras)";
    r.skeleton.clear();
    r.timings.total_ms = static_cast<double>(total.elapsed_us()) * 1e-3;
    return r;
  }

  t.restart();
  cleanup_.apply(r.hull, r.hull_stats);
  r.timings.cleanup_ms = static_cast<double>(t.elapsed_us()) * 1e-3;

  t.restart();
  r.skeleton = r.hull;  // same size: copies into the existing allocation
  if (options_.skeletoniser == Skeletoniser::kD6i1d)
    r.thin = d6i1d_.thin(r.skeleton);
  else if (!on_gpu([&] { r.thin = cuda_->thin(r.skeleton); }))
    r.thin = ck3_.thin(r.skeleton);
  r.timings.thin_ms = static_cast<double>(t.elapsed_us()) * 1e-3;

  t.restart();
  r.skeleton.for_each([&](int x, int y, int z) { r.skeleton_voxels.emplace_back(x, y, z); });
  r.timings.extract_ms = static_cast<double>(t.elapsed_us()) * 1e-3;
  r.valid = true;
  r.timings.total_ms = static_cast<double>(total.elapsed_us()) * 1e-3;
  return r;
}

}  // namespace hullpose::fusion
