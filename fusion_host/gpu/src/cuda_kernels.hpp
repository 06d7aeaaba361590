#pragma once
// Kernel launchers of the CUDA backend (src/cuda_kernels.cu), callable from host C++ (no CUDA
// types). Each returns the launch's cudaError_t as an int (0 = success). Internal to hullpose_gpu.
#include <cstddef>
#include <cstdint>

#include "hullpose/carve/voxel_test.hpp"
#include "hullpose/thin/ck3_rules.hpp"

namespace hullpose::gpu::detail {

// ---- carving ------------------------------------------------------------------------------
struct CarveArgs {
  const carve::CameraParams* cams = nullptr;  // device, present cameras only
  const carve::MaskView* masks = nullptr;     // device, same order (data are device pointers)
  int ncams = 0, tolerance = 0;
  const double* centre_x = nullptr;  // device: voxel centre coordinates per axis (mm)
  const double* centre_y = nullptr;
  const double* centre_z = nullptr;
  int nx = 0, ny = 0, nz = 0;
  uint32_t* hull = nullptr;  // device: BitGrid words as 32-bit halves, 2 * words_per_row per row
  int words_per_row = 0;
};
int launch_carve(const CarveArgs& a);

// ---- CK3 ----------------------------------------------------------------------------------
// The padded bit volume (2 voxels of background on every side, x stride 1 << shift) and its
// per-voxel flags, on the device.
struct DeviceVolume {
  uint64_t* rows = nullptr;   // (py * pz) rows of `words` words; one spare word per row
  uint32_t* flags = nullptr;  // (py * pz) << shift (32 bits: atomicCAS when the border grows)
  int shift = 0, py = 0, pz = 0, px = 0;
  uint32_t mask = 0;
  uint32_t words = 0;
  int off27[27] = {};
  int faces[6] = {};
};

enum class Ck3Pass : int {
  kCk3Surface,
  kCk3Candidate,
  kIsthmusPairs,
  kIsthmusEdges,
  kIsthmusSettle,
  kLevel2,
  kLevel1
};

// Counters on the device, read back once per iteration.
struct Ck3Counters {
  uint32_t next = 0;         // entries of the next border list
  uint32_t deleted = 0;      // deletions this iteration
  uint32_t constrained = 0;  // voxels that joined K this iteration
  uint32_t k_total = 0;      // |K|
};

// Border voxels of the loaded object: flags = kInB, appended to `border`, count in c->next.
int launch_ck3_border(const DeviceVolume& v, uint32_t* border, Ck3Counters* c);
int launch_ck3_classify(const DeviceVolume& v, const thin::ck3::RuleTables* t, thin::CurveRule rule,
                        const uint32_t* border, uint32_t n, uint32_t* codes);
int launch_ck3_pass(Ck3Pass pass, const DeviceVolume& v, const thin::ck3::RuleTables* t,
                    const uint32_t* border, uint32_t n, const uint32_t* codes);
// Level 0: appends the border positions of deleted voxels to `deleted` (count in c->deleted).
int launch_ck3_level0(const DeviceVolume& v, const thin::ck3::RuleTables* t,
                      thin::ZeroCliqueTest test, const uint32_t* border, uint32_t n,
                      const uint32_t* codes, uint32_t* deleted, Ck3Counters* c);
// Clears the deleted voxels, moves K out of the border list, appends the survivors and the newly
// exposed voxels to `next` (c->next), K to `k_list` (c->k_total, c->constrained).
int launch_ck3_settle(const DeviceVolume& v, const uint32_t* border, uint32_t n,
                      const uint32_t* deleted, uint32_t max_deleted, uint32_t* next,
                      uint32_t* k_list, Ck3Counters* c);

}  // namespace hullpose::gpu::detail
