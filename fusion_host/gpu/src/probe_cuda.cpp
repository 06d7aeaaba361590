// Probe through the CUDA runtime. cudaGetDeviceCount fails cleanly (no abort) when the driver
// or the device is missing, which is the normal case on CI and on most fusion hosts.
#include <cuda_runtime_api.h>

#include <string>

#include "hullpose/gpu/backend.hpp"

namespace hullpose::gpu {

bool built_with_cuda() {
  return true;
}

DeviceInfo probe_device() {
  DeviceInfo info;
  int count = 0;
  const cudaError_t err = cudaGetDeviceCount(&count);
  if (err != cudaSuccess) {
    info.reason = std::string("no CUDA device: ") + cudaGetErrorString(err);
    return info;
  }
  if (count == 0) {
    info.reason = "no CUDA device: the driver reports 0 devices";
    return info;
  }
  cudaDeviceProp prop{};
  if (const cudaError_t e = cudaGetDeviceProperties(&prop, 0); e != cudaSuccess) {
    info.reason = std::string("CUDA device 0 unusable: ") + cudaGetErrorString(e);
    return info;
  }
  info.available = true;
  info.name = prop.name;
  info.compute_major = prop.major;
  info.compute_minor = prop.minor;
  info.memory_bytes = prop.totalGlobalMem;
  return info;
}

}  // namespace hullpose::gpu
