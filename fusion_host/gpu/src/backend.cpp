#include "hullpose/gpu/backend.hpp"

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose::gpu {

HULLPOSE_LOG_CATEGORY(Gpu, "gpu")

Backend parse_backend(std::string_view text) {
  if (text == "auto") return Backend::kAuto;
  if (text == "cpu") return Backend::kCpu;
  if (text == "cuda") return Backend::kCuda;
  HULLPOSE_THROW("--backend '" << text << "' is not one of auto, cpu, cuda");
}

std::string_view to_string(Backend backend) {
  switch (backend) {
    case Backend::kAuto:
      return "auto";
    case Backend::kCpu:
      return "cpu";
    case Backend::kCuda:
      return "cuda";
  }
  return "?";
}

Backend resolve_backend(Backend requested, DeviceInfo* device_out) {
  if (requested == Backend::kCpu) return Backend::kCpu;
  const DeviceInfo device = probe_device();
  if (device_out) *device_out = device;
  if (device.available) {
    HULLPOSE_LOG(Gpu, Info) << "CUDA device: " << device.name << " (compute "
                            << device.compute_major << "." << device.compute_minor << ", "
                            << device.memory_bytes / (1024 * 1024) << " MiB)";
    return Backend::kCuda;
  }
  HULLPOSE_THROW_UNLESS(requested == Backend::kAuto, "--backend cuda: " << device.reason);
  HULLPOSE_LOG(Gpu, Info) << "backend auto: using the CPU (" << device.reason << ")";
  return Backend::kCpu;
}

}  // namespace hullpose::gpu
