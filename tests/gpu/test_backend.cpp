// Runs everywhere: on a machine without a GPU (CI) the probe must say so cleanly and auto must
// fall back to the CPU; on a machine with one, auto must pick it.
#include <catch2/catch.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/gpu/backend.hpp"

using namespace hullpose::gpu;

TEST_CASE("backend names parse, and bad ones are rejected") {
  CHECK(parse_backend("auto") == Backend::kAuto);
  CHECK(parse_backend("cpu") == Backend::kCpu);
  CHECK(parse_backend("cuda") == Backend::kCuda);
  CHECK_THROWS_WITH(parse_backend("opencl"), Catch::Contains("'opencl'") && Catch::Contains("auto, cpu, cuda"));
  CHECK(to_string(Backend::kCuda) == "cuda");
}

TEST_CASE("the build reports whether it has the CUDA backend") {
  CHECK(built_with_cuda() == static_cast<bool>(HULLPOSE_HAVE_CUDA));
}

TEST_CASE("probe and auto agree; cpu never probes") {
  const DeviceInfo device = probe_device();
  CHECK(resolve_backend(Backend::kCpu) == Backend::kCpu);
  if (device.available) {
    CHECK(device.reason.empty());
    CHECK_FALSE(device.name.empty());
    CHECK(resolve_backend(Backend::kAuto) == Backend::kCuda);
    CHECK(resolve_backend(Backend::kCuda) == Backend::kCuda);
  } else {
    INFO("probe: " << device.reason);
    CHECK_FALSE(device.reason.empty());
    CHECK(resolve_backend(Backend::kAuto) == Backend::kCpu);
    CHECK_THROWS_WITH(resolve_backend(Backend::kCuda), Catch::Contains("--backend cuda") && Catch::Contains(device.reason));
  }
}
