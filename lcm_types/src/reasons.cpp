#include "hullpose/msg/reasons.hpp"

#include <array>
#include <hullpose_msg/skeleton_t.hpp>

namespace hullpose::msg {
namespace {
using S = hullpose_msg::skeleton_t;
constexpr std::array<const char*, kNumReasons> kReasonNames = {
    "ok", "too_few_cameras", "empty_hull", "invalid_tree", "pose_jump", "fit_failed"};
static_assert(S::REASON_OK == 0 && S::REASON_TOO_FEW_CAMERAS == 1 && S::REASON_EMPTY_HULL == 2 &&
                  S::REASON_INVALID_TREE == 3 && S::REASON_POSE_JUMP == 4 &&
                  S::REASON_FIT_FAILED == 5,
              "kReasonNames follows skeleton_t.lcm's REASON_* order");
}  // namespace

std::string reason_name(int reason) {
  if (reason >= 0 && reason < kNumReasons) return kReasonNames[static_cast<size_t>(reason)];
  return "reason_" + std::to_string(reason);
}

}  // namespace hullpose::msg
