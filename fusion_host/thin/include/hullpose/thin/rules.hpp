#pragma once
// The thinning options' enums, without dependencies, for the CUDA sources too.
#include <cstdint>

namespace hullpose::thin {

enum class CurveRule : uint8_t {
  kUltimate,  // no constraint: the ultimate skeleton (tests, notes §3)
  kCk3,  // thesis' curve(v): Pink lskelCK3 residual points + 2D isthmus (notes §3.3, §3.4) —
         // default
  kIsthmus,   // CK3a: 1D isthmuses accumulated into K (notes §3.1)
  kEndVoxel,  // EK3: voxels with exactly one 26-neighbour accumulated into K (notes §3.2)
};

enum class ZeroCliqueTest : uint8_t {
  kSpan3,      // correct: Q ∩ X spans all three axes (notes §2.4)
  kAntipodal,  // Pink / DGtal: an antipodal pair (misses cases, breaks topology; comparison only)
};

}  // namespace hullpose::thin
