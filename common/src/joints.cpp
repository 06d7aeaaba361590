#include "hullpose/common/joints.hpp"

#include <string>

namespace hullpose {

std::optional<Joint> joint_from_name(std::string_view name) {
  for (int i = 0; i < kNumJoints; ++i)
    if (kJointNames[static_cast<size_t>(i)] == name) return static_cast<Joint>(i);
  return std::nullopt;
}

Joint mirror(Joint j) {
  const std::string_view n = name(j);
  if (n.size() < 2 || (n[0] != 'L' && n[0] != 'R') || n == "LBack") return j;
  std::string other(n);
  other[0] = n[0] == 'L' ? 'R' : 'L';
  return joint_from_name(other).value_or(j);
}

}  // namespace hullpose
