#pragma once
// The one table of skeleton_t's REASON_* codes (lcm_types/hullpose_msg/skeleton_t.lcm) and their
// names, as logs, JSON summaries, the listener and hullpose-eval print them. A new reason goes
// into skeleton_t.lcm and into kReasonNames in reasons.cpp, in the same order.
#include <cstdint>
#include <string>

namespace hullpose::msg {

// "ok", "too_few_cameras", "empty_hull", "invalid_tree", "pose_jump", "fit_failed"; an unknown
// code (a newer sender) is "reason_<code>".
std::string reason_name(int reason);
// Number of codes the table names (0 .. kNumReasons-1).
inline constexpr int kNumReasons = 6;

}  // namespace hullpose::msg
