#pragma once
// The fusion core: the silhouettes of one trigger instant in, the visual hull and its curve
// skeleton out, with per-stage timings. Stages: carve (hullpose_carve) -> clean-up (keep the
// person's component(s), fill small cavities, hull statistics) -> thin (hullpose_thin) ->
// skeleton voxel list for the pose stage.
//
// Lifecycle: construct once per (rig, options) — this precomputes the carving tables — then call
// process() per frame. The result lives in the FusionCore and is overwritten by the next call;
// every buffer is reused, so at steady state a frame allocates nothing.
// Per-frame problems (missing or malformed views, too few cameras, empty hull) never throw:
// the result is marked invalid with a reason and counted in the Counters given at construction.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <span>
#include <vector>

#include "hullpose/carve/carver.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"
#include "hullpose/fusion/hull_cleanup.hpp"
#include "hullpose/gpu/backend.hpp"
#include "hullpose/thin/thinning.hpp"

namespace hullpose::gpu {
class CudaFusion;
}

namespace hullpose::fusion {

enum class Skeletoniser { kCk3, kD6i1d };

struct FusionOptions {
  int resolution = 64;  // voxels along the capture volume's longest axis
  int tolerance = 0;    // carving: a voxel may miss in k present cameras
  // Carving and CK3 threads. Each CK3 iteration has 5 barriers: more than one thread pays only on
  // cores this process has to itself (measured: 2 threads on the shared, loaded 2-core build
  // machine are several times slower than 1).
  int threads = 1;
  Skeletoniser skeletoniser = Skeletoniser::kCk3;
  thin::CurveRule curve_rule = thin::CurveRule::kCk3;  // CK3's curve constraint
  CleanupOptions cleanup;
  // Carving and CK3 on the CPU or the GPU (`--backend`); auto = CUDA if this build has it and a
  // device is present, else the CPU (logged). D6I1D and clean-up always run on the CPU.
  gpu::Backend backend = gpu::Backend::kAuto;
};

struct StageTimings {
  double carve_ms = 0, cleanup_ms = 0, thin_ms = 0, extract_ms = 0, total_ms = 0;
};

enum class FusionFailure { kNone, kTooFewViews, kEmptyHull };
const char* to_string(FusionFailure failure);

struct FusionResult {
  bool valid = false;
  FusionFailure failure = FusionFailure::kNone;
  VoxelGridSpec grid;  // voxel coordinates below are in this grid
  carve::CarveReport carve;
  HullStats hull_stats;
  thin::ThinStats thin;
  StageTimings timings;
  BitGrid hull;  // after clean-up
  BitGrid skeleton;
  std::vector<Eigen::Vector3i> skeleton_voxels;  // x-fastest order
};

class FusionCore {
 public:
  // Throws hullpose::Error on a bad rig or options, or `--backend cuda` without a usable device.
  // `counters`, if given, must outlive this.
  FusionCore(const Rig& rig, const FusionOptions& options, Counters* counters = nullptr);
  ~FusionCore();
  FusionCore(const FusionCore&) = delete;
  FusionCore& operator=(const FusionCore&) = delete;

  // views[i] is rig.cameras[i]'s silhouette (CV_8UC1, 255 = person) or an empty Mat if it sent
  // nothing; fg_boxes optionally its foreground box (the silhouette codec's ROI).
  const FusionResult& process(std::span<const cv::Mat> views,
                              std::span<const PixelRoi> fg_boxes = {});

  const VoxelGridSpec& grid() const { return carver_.grid(); }
  const FusionOptions& options() const { return options_; }
  // The backend in use: kCpu or kCuda (auto resolved at construction; kCpu from the first CUDA
  // error on, counted "fusion.cuda_error").
  gpu::Backend backend() const { return backend_; }

 private:
  // Runs `step` on the GPU backend; false (and the CPU from now on) without one or when it fails.
  template <class Step>
  bool on_gpu(Step&& step);

  FusionOptions options_;
  Counters* counters_;
  carve::Carver carver_;
  gpu::Backend backend_;
  std::unique_ptr<gpu::CudaFusion> cuda_;  // set iff backend_ == kCuda
  HullCleanup cleanup_;
  thin::Ck3Thinner ck3_;
  thin::D6i1dThinner d6i1d_;
  FusionResult result_;
};

}  // namespace hullpose::fusion
