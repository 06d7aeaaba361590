#pragma once
// Volume sizes of the fusion unit tests. `make test-asan` runs them again in a Debug build under
// AddressSanitizer + UBSan, where per-rig precomputation and the brute-force reference are ~50x
// slower: there they use 32³ grids (the same code paths: every octree level, both carving
// paths, all thinning passes). The release run (`make test`) keeps 64³.
namespace hullpose::fusion::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif
inline constexpr int kUnitResolution = kSanitizerBuild ? 32 : 64;
// Hull sizes scale with the cube of the resolution.
inline constexpr int kVoxelScale = kSanitizerBuild ? 8 : 1;

}  // namespace hullpose::fusion::testing
