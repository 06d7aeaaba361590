// Runs everywhere: on a machine without a GPU (CI) the probe must say so cleanly and auto must
// fall back to the CPU (also inside the fusion core); on a machine with one, auto must pick it.
#include <catch2/catch.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/fusion/fusion_core.hpp"
#include "hullpose/gpu/backend.hpp"
#include "hullpose/gpu/cuda_fusion.hpp"
#include "support/synthetic_scene.hpp"

using namespace hullpose::gpu;

TEST_CASE("backend names parse, and bad ones are rejected") {
  CHECK(parse_backend("auto") == Backend::kAuto);
  CHECK(parse_backend("cpu") == Backend::kCpu);
  CHECK(parse_backend("cuda") == Backend::kCuda);
  CHECK_THROWS_WITH(parse_backend("opencl"),
                    Catch::Contains("'opencl'") && Catch::Contains("auto, cpu, cuda"));
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
    CHECK_THROWS_WITH(resolve_backend(Backend::kCuda),
                      Catch::Contains("--backend cuda") && Catch::Contains(device.reason));
  }
}

TEST_CASE("the fusion core resolves its backend: auto falls back to the CPU, cuda needs a device") {
  namespace ft = hullpose::fusion::testing;
  const hullpose::Rig rig = ft::thesis_like_rig(160, 120);
  hullpose::fusion::FusionOptions opt;
  opt.resolution = 32;
  const DeviceInfo device = probe_device();
  opt.backend = Backend::kAuto;
  hullpose::fusion::FusionCore automatic(rig, opt);
  CHECK(automatic.backend() == (device.available ? Backend::kCuda : Backend::kCpu));
  opt.backend = Backend::kCpu;
  hullpose::fusion::FusionCore cpu(rig, opt);
  CHECK(cpu.backend() == Backend::kCpu);
  // Whatever auto picked, the frame's result is the CPU's.
  const auto views = ft::render_views(rig, ft::human_capsules(0.3));
  const hullpose::fusion::BitGrid hull = automatic.process(views).hull;
  CHECK(cpu.process(views).hull == hull);
  if (!device.available) {
    opt.backend = Backend::kCuda;
    CHECK_THROWS_WITH(hullpose::fusion::FusionCore(rig, opt),
                      Catch::Contains("--backend cuda") && Catch::Contains(device.reason));
    // The backend class itself refuses cleanly too.
    hullpose::carve::Carver carver(rig, {32, 0, 1});
    CHECK_THROWS_WITH(CudaFusion(carver, {}),
                      Catch::Contains("CUDA backend") && Catch::Contains(device.reason));
  }
}
