#pragma once
// Bounds checks of LCM-encoded hullpose messages, run on bytes from the network BEFORE the
// lcm-gen decoder: lcm-gen's C++ decoders trust the length fields (a string length of 0 or less
// makes std::string::assign throw; a negative or huge array size makes std::vector::resize throw
// or allocate gigabytes before the bounds check). Each function walks the message layout of
// lcm_types/hullpose_msg/<type>.lcm and returns true only if every length is sane and the
// message fills `size` exactly. Keep in step with the .lcm files (tests/rig/test_lcm_wire.cpp
// checks that encoded messages pass and that truncations and bad lengths fail).
#include <cstddef>
#include <cstdint>

namespace hullpose::wire {

inline constexpr int32_t kMaxString = 4096;
inline constexpr int32_t kMaxPayload = 1 << 20;
inline constexpr int32_t kMaxJoints = 256;

bool silhouette_ok(const void* data, size_t size);
bool trigger_ok(const void* data, size_t size);
bool skeleton_ok(const void* data, size_t size);
// node_status_t: stage and counter lists of at most kMaxJoints names each.
bool status_ok(const void* data, size_t size);

}  // namespace hullpose::wire
