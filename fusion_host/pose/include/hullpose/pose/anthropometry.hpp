#pragma once
// Body proportions the tree and the fit share, all derived from the model's bone ratios
// (common/joints.hpp = thesis Table 6.7), so there is one source of truth. Paper 5's Table 1
// expresses the same proportions relative to the longest hand-to-foot path instead of the
// stature; that path is kLongestPath statures long (1.305), which is exactly the factor between
// the two tables.
#include "hullpose/common/joints.hpp"

namespace hullpose::pose {

// Length of the bone ending in `child`, in statures (every joint but Chest has one parent bone).
constexpr double bone_ratio(Joint child) {
  const int b = bone_to(child);
  return b < 0 ? 0 : kBones[static_cast<size_t>(b)].stature_ratio;
}

namespace ratio {
// Origin (where arms, neck and torso meet, ~Chest) to the top of the head.
inline constexpr double kNeckChain =
    bone_ratio(Joint::Neck) + bone_ratio(Joint::Head) + bone_ratio(Joint::HeadTop);
// Origin to a fingertip.
inline constexpr double kArmChain = bone_ratio(Joint::LSho) + bone_ratio(Joint::LElb) +
                                    bone_ratio(Joint::LHand) + bone_ratio(Joint::LFTip);
// Chest to the lower back.
inline constexpr double kTorso =
    bone_ratio(Joint::UBack) + bone_ratio(Joint::Back) + bone_ratio(Joint::LBack);
// Lower back to a toe tip.
inline constexpr double kLegChain = bone_ratio(Joint::LHip) + bone_ratio(Joint::LKne) +
                                    bone_ratio(Joint::LAnk) + bone_ratio(Joint::LFoot) +
                                    bone_ratio(Joint::LToe);
// Paper 5's reference length: fingertip to toe tip through the torso.
inline constexpr double kLongestPath = kArmChain + kTorso + kLegChain;
// Toe tip to head top along the bones: 1 by construction of Table 6.7 (the stature).
inline constexpr double kStaturePath = kLegChain + kTorso + kNeckChain;
}  // namespace ratio

}  // namespace hullpose::pose
