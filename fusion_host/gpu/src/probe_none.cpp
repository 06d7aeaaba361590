// Probe for builds without the CUDA backend.
#include "hullpose/gpu/backend.hpp"

namespace hullpose::gpu {

bool built_with_cuda() {
  return false;
}

DeviceInfo probe_device() {
  DeviceInfo info;
  info.reason = "this build has no CUDA backend (nvcc was not found at configure time)";
  return info;
}

}  // namespace hullpose::gpu
