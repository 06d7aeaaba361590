#pragma once
// CUDA backend of the fusion core (issue 8): carving and CK3 on the GPU, voxel for voxel equal
// to the CPU path. The per-voxel logic is the CPU's own (carve/voxel_test.hpp,
// thin/ck3_rules.hpp, HULLPOSE_HD), so the CPU tests exercise the code the kernels run.
//
// Carving projects every voxel centre (one thread per voxel, a warp writes 32 bits of a row):
// on a GPU the brute-force definition is fast enough and is the reference itself. Silhouettes go
// up raw, only their foreground box (pixels outside it are background, as on the CPU); decoding
// the codec on the device is not done. CK3 runs the CPU's passes as kernels over a border list
// kept on the device; one 16-byte read-back per iteration decides whether to go on.
//
// Lifecycle: construct once per (rig, resolution): every device buffer (masks, bit volume, flags,
// lists, LUTs) is allocated there; carve() and thin() allocate nothing. No managed memory.
// Throws hullpose::Error when this build has no CUDA backend or no device is usable, and on CUDA
// errors (with the call that failed).
#include <memory>
#include <span>

#include "hullpose/carve/carver.hpp"
#include "hullpose/thin/thinning.hpp"

namespace hullpose::gpu {

// Per-stage GPU times of the last call (CUDA events), milliseconds.
struct GpuStageTimes {
  double upload_ms = 0, kernels_ms = 0, download_ms = 0;
};

class CudaFusion {
 public:
  // `carver` (its rig, grid and view checks) must outlive this. Only the CK3 thinner runs on the
  // GPU: `thin_options.rule` and `zero_clique` are honoured, threads are not used.
  CudaFusion(const carve::Carver& carver, const thin::ThinOptions& thin_options);
  ~CudaFusion();
  CudaFusion(const CudaFusion&) = delete;
  CudaFusion& operator=(const CudaFusion&) = delete;

  // Same contract and result as carve::Carver::carve.
  void carve(std::span<const cv::Mat> views, fusion::BitGrid& hull, carve::CarveReport& report,
             std::span<const PixelRoi> fg_boxes = {});
  // Same result as thin::Ck3Thinner::thin(volume) (no constraint set). `volume` has the grid's
  // dims.
  thin::ThinStats thin(fusion::BitGrid& volume);

  const GpuStageTimes& carve_times() const;
  const GpuStageTimes& thin_times() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hullpose::gpu
