#pragma once
// Compute backend selection for the fusion host: `--backend auto|cpu|cuda`.
// auto = CUDA if this build has the CUDA backend and a usable device is present, else CPU.
// Asking for cuda explicitly without a device is a configuration error (hullpose::Error)
// that says why (built without CUDA, no driver, no device).
#include <string>
#include <string_view>

namespace hullpose::gpu {

enum class Backend { kAuto, kCpu, kCuda };

struct DeviceInfo {
  bool available = false;
  std::string reason;  // why not available ("" if it is)
  std::string name;
  int compute_major = 0, compute_minor = 0;
  size_t memory_bytes = 0;
};

// True if this binary was built with the CUDA backend (nvcc found at configure time).
bool built_with_cuda();
// Looks for a CUDA device; never throws, never aborts.
DeviceInfo probe_device();

// Throws hullpose::Error on anything but "auto", "cpu", "cuda".
Backend parse_backend(std::string_view text);
std::string_view to_string(Backend backend);

// Resolves auto and validates cuda; returns kCpu or kCuda. `device` receives the probe result.
Backend resolve_backend(Backend requested, DeviceInfo* device = nullptr);

}  // namespace hullpose::gpu
