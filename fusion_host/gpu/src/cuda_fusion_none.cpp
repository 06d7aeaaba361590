// CudaFusion for builds without the CUDA backend: constructing it is a clear configuration error.
#include "hullpose/common/check.hpp"
#include "hullpose/gpu/backend.hpp"
#include "hullpose/gpu/cuda_fusion.hpp"

namespace hullpose::gpu {

struct CudaFusion::Impl {
  GpuStageTimes times;
};

CudaFusion::CudaFusion(const carve::Carver&, const thin::ThinOptions&) {
  HULLPOSE_THROW("CUDA backend: " << probe_device().reason);
}
CudaFusion::~CudaFusion() = default;
void CudaFusion::carve(std::span<const cv::Mat>, fusion::BitGrid&, carve::CarveReport&,
                       std::span<const PixelRoi>) {
  HULLPOSE_THROW("CUDA backend: not built");
}
thin::ThinStats CudaFusion::thin(fusion::BitGrid&) {
  HULLPOSE_THROW("CUDA backend: not built");
}
const GpuStageTimes& CudaFusion::carve_times() const {
  return impl_->times;
}
const GpuStageTimes& CudaFusion::thin_times() const {
  return impl_->times;
}

}  // namespace hullpose::gpu
