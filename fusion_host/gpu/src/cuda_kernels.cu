// Kernels of the CUDA backend. The per-voxel decisions are the CPU's (voxel_test.hpp,
// ck3_rules.hpp); compiled with --fmad=false so the projection rounds exactly as on the CPU
// (hullpose_carve is built with -ffp-contract=off).
#include <cuda_runtime.h>

#include "cuda_kernels.hpp"

namespace hullpose::gpu::detail {

namespace {

constexpr int kThreads = 256;

unsigned blocks_for(uint32_t n) {
  return (n + kThreads - 1) / kThreads;
}

// ---- carving ------------------------------------------------------------------------------

// Block (32, 8): a warp is 32 consecutive x of one row; lane 0 writes the warp's ballot, one
// 32-bit half of a BitGrid word.
__global__ void carve_kernel(CarveArgs a) {
  const int x = static_cast<int>(blockIdx.x * 32 + threadIdx.x);
  const int y = static_cast<int>(blockIdx.y * blockDim.y + threadIdx.y);
  const int z = static_cast<int>(blockIdx.z);
  bool kept = false;
  if (x < a.nx && y < a.ny)
    kept = carve::voxel_kept(a.cams, a.masks, a.ncams, a.tolerance, a.centre_x[x], a.centre_y[y],
                             a.centre_z[z]);
  const unsigned ballot = __ballot_sync(0xffffffffu, kept);
  if (threadIdx.x == 0 && y < a.ny)
    a.hull[(static_cast<size_t>(z) * a.ny + y) * (2 * static_cast<size_t>(a.words_per_row)) +
           blockIdx.x] = ballot;
}

// ---- CK3 ----------------------------------------------------------------------------------

// The volume as ck3_rules.hpp reads it.
struct View {
  DeviceVolume v;
  HULLPOSE_HD uint8_t flags(uint32_t idx) const { return static_cast<uint8_t>(v.flags[idx]); }
  HULLPOSE_HD bool get(uint32_t idx) const {
    const uint32_t row = idx >> v.shift, x = idx & v.mask;
    return (v.rows[static_cast<size_t>(row) * v.words + (x >> 6)] >> (x & 63) & 1u) != 0;
  }
  HULLPOSE_HD int off27(int bit) const { return v.off27[bit]; }
  HULLPOSE_HD int face(int d) const { return v.faces[d]; }
  // The 27-bit code (notes §0), from aligned word reads (x >= 2: the padding).
  __device__ uint32_t code(uint32_t idx) const {
    const uint32_t row = idx >> v.shift, x = (idx & v.mask) - 1;
    const uint32_t wi = x >> 6, b = x & 63;
    uint32_t c = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        const uint64_t* w =
            v.rows + static_cast<size_t>(static_cast<int>(row) + dy + dz * v.py) * v.words;
        uint64_t bits = w[wi] >> b;
        if (b > 61) bits |= w[wi + 1] << (64 - b);
        c |= static_cast<uint32_t>(bits & 7u) << ((dz + 1) * 9 + (dy + 1) * 3);
      }
    return c;
  }
};

__global__ void border_kernel(View view, uint32_t* border, Ck3Counters* c) {
  // One thread per voxel of the unpadded box.
  const DeviceVolume& v = view.v;
  const uint32_t nx = static_cast<uint32_t>(v.px - 4), ny = static_cast<uint32_t>(v.py - 4),
                 nz = static_cast<uint32_t>(v.pz - 4);
  const uint64_t i = static_cast<uint64_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  if (i >= static_cast<uint64_t>(nx) * ny * nz) return;
  const uint32_t x = static_cast<uint32_t>(i % nx) + 2, y = static_cast<uint32_t>(i / nx % ny) + 2,
                 z = static_cast<uint32_t>(i / nx / ny) + 2;
  const uint32_t idx = ((z * static_cast<uint32_t>(v.py) + y) << v.shift) | x;
  if (!view.get(idx)) return;
  bool interior = true;
  for (int d = 0; d < 6; ++d)
    interior = interior && view.get(idx + static_cast<uint32_t>(v.faces[d]));
  if (interior) return;
  v.flags[idx] = thin::ck3::kInB;
  border[atomicAdd(&c->next, 1u)] = idx;
}

__global__ void classify_kernel(View view, const thin::ck3::RuleTables* t, thin::CurveRule rule,
                                const uint32_t* border, uint32_t n, uint32_t* codes) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const uint32_t idx = border[i];
  const uint32_t code = view.code(idx);
  codes[i] = code;
  view.v.flags[idx] = thin::ck3::classify(*t, rule, code);
}

__global__ void pass_kernel(Ck3Pass pass, View view, const thin::ck3::RuleTables* t,
                            const uint32_t* border, uint32_t n, const uint32_t* codes) {
  namespace r = thin::ck3;
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const uint32_t idx = border[i], code = codes[i];
  const uint8_t f = view.flags(idx);
  uint8_t nf = f;
  switch (pass) {
    case Ck3Pass::kCk3Surface:
      nf = r::ck3_surface(view, *t, idx, code, f);
      break;
    case Ck3Pass::kCk3Candidate:
      nf = r::ck3_candidate(view, *t, idx, code, f);
      break;
    case Ck3Pass::kIsthmusPairs:
      nf = r::isthmus_pairs(view, *t, idx, code, f);
      break;
    case Ck3Pass::kIsthmusEdges:
      nf = r::isthmus_edges(view, *t, idx, code, f);
      break;
    case Ck3Pass::kIsthmusSettle:
      nf = r::isthmus_settle(f);
      break;
    case Ck3Pass::kLevel2:
      nf = r::level2(view, *t, idx, code, f);
      break;
    case Ck3Pass::kLevel1:
      nf = r::level1(view, *t, idx, code, f);
      break;
  }
  if (nf != f) view.v.flags[idx] = nf;
}

__global__ void level0_kernel(View view, const thin::ck3::RuleTables* t, thin::ZeroCliqueTest test,
                              const uint32_t* border, uint32_t n, const uint32_t* codes,
                              uint32_t* deleted, Ck3Counters* c) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const uint32_t idx = border[i];
  if (thin::ck3::level0_deletes(view, *t, idx, codes[i], view.flags(idx), test))
    deleted[atomicAdd(&c->deleted, 1u)] = i;
}

__global__ void delete_kernel(View view, const uint32_t* border, const uint32_t* deleted,
                              const Ck3Counters* c) {
  const uint32_t j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= c->deleted) return;
  const uint32_t idx = border[deleted[j]];
  const DeviceVolume& v = view.v;
  const uint32_t row = idx >> v.shift, x = idx & v.mask;
  atomicAnd(
      reinterpret_cast<unsigned long long*>(&v.rows[static_cast<size_t>(row) * v.words + (x >> 6)]),
      ~(1ull << (x & 63)));
  v.flags[idx] = 0;
}

// Survivors stay in the border list, K leaves it (after the deletions: deleted voxels have flags
// 0).
__global__ void rebuild_kernel(View view, const uint32_t* border, uint32_t n, uint32_t* next,
                               uint32_t* k_list, Ck3Counters* c) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const uint32_t idx = border[i];
  const uint32_t f = view.v.flags[idx];
  if (f == 0) return;
  if (f & thin::ck3::kK) {
    view.v.flags[idx] = thin::ck3::kK;
    k_list[atomicAdd(&c->k_total, 1u)] = idx;
    atomicAdd(&c->constrained, 1u);
  } else {
    next[atomicAdd(&c->next, 1u)] = idx;
  }
}

// Newly exposed voxels join the border list once (the flag word goes 0 -> kInB atomically).
__global__ void grow_kernel(View view, const uint32_t* border, const uint32_t* deleted,
                            uint32_t* next, Ck3Counters* c) {
  const uint32_t j = blockIdx.x * blockDim.x + threadIdx.x;
  if (j >= c->deleted) return;
  const uint32_t idx = border[deleted[j]];
  for (int d = 0; d < 6; ++d) {
    const uint32_t q = idx + static_cast<uint32_t>(view.v.faces[d]);
    if (view.get(q) &&
        atomicCAS(&view.v.flags[q], 0u, static_cast<uint32_t>(thin::ck3::kInB)) == 0u)
      next[atomicAdd(&c->next, 1u)] = q;
  }
}

int last_error() {
  return static_cast<int>(cudaGetLastError());
}

}  // namespace

int launch_carve(const CarveArgs& a) {
  const dim3 block(32, 8);
  const dim3 grid(static_cast<unsigned>((a.nx + 31) / 32), static_cast<unsigned>((a.ny + 7) / 8),
                  static_cast<unsigned>(a.nz));
  carve_kernel<<<grid, block>>>(a);
  return last_error();
}

int launch_ck3_border(const DeviceVolume& v, uint32_t* border, Ck3Counters* c) {
  const uint64_t n = static_cast<uint64_t>(v.px - 4) * (v.py - 4) * (v.pz - 4);
  border_kernel<<<static_cast<unsigned>((n + kThreads - 1) / kThreads), kThreads>>>(View{v}, border,
                                                                                    c);
  return last_error();
}

int launch_ck3_classify(const DeviceVolume& v, const thin::ck3::RuleTables* t, thin::CurveRule rule,
                        const uint32_t* border, uint32_t n, uint32_t* codes) {
  if (n == 0) return 0;
  classify_kernel<<<blocks_for(n), kThreads>>>(View{v}, t, rule, border, n, codes);
  return last_error();
}

int launch_ck3_pass(Ck3Pass pass, const DeviceVolume& v, const thin::ck3::RuleTables* t,
                    const uint32_t* border, uint32_t n, const uint32_t* codes) {
  if (n == 0) return 0;
  pass_kernel<<<blocks_for(n), kThreads>>>(pass, View{v}, t, border, n, codes);
  return last_error();
}

int launch_ck3_level0(const DeviceVolume& v, const thin::ck3::RuleTables* t,
                      thin::ZeroCliqueTest test, const uint32_t* border, uint32_t n,
                      const uint32_t* codes, uint32_t* deleted, Ck3Counters* c) {
  if (n == 0) return 0;
  level0_kernel<<<blocks_for(n), kThreads>>>(View{v}, t, test, border, n, codes, deleted, c);
  return last_error();
}

int launch_ck3_settle(const DeviceVolume& v, const uint32_t* border, uint32_t n,
                      const uint32_t* deleted, uint32_t max_deleted, uint32_t* next,
                      uint32_t* k_list, Ck3Counters* c) {
  if (n == 0) return 0;
  // The deletion count is on the device: launch for the most there can be, threads past it return.
  delete_kernel<<<blocks_for(max_deleted), kThreads>>>(View{v}, border, deleted, c);
  rebuild_kernel<<<blocks_for(n), kThreads>>>(View{v}, border, n, next, k_list, c);
  grow_kernel<<<blocks_for(max_deleted), kThreads>>>(View{v}, border, deleted, next, c);
  return last_error();
}

}  // namespace hullpose::gpu::detail
