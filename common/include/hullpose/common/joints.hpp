#pragma once
// The 25-joint / 24-bone articulated model of the thesis (Fig. 6.2, 6.3, Table 6.7). This
// order is the wire order of skeleton_t, the column order of ground-truth and estimate
// files, and the index used everywhere else.
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace hullpose {

enum class Joint : uint8_t {
  HeadTop,
  Head,
  Neck,
  Chest,
  LSho,
  RSho,
  LElb,
  RElb,
  LHand,
  RHand,
  LFTip,
  RFTip,
  UBack,
  Back,
  LBack,
  LHip,
  RHip,
  LKne,
  RKne,
  LAnk,
  RAnk,
  LFoot,
  RFoot,
  LToe,
  RToe
};
inline constexpr int kNumJoints = 25;
inline constexpr int kNumBones = 24;

inline constexpr std::array<std::string_view, kNumJoints> kJointNames = {
    "HeadTop", "Head",  "Neck",  "Chest", "LSho",  "RSho",  "LElb", "RElb", "LHand",
    "RHand",   "LFTip", "RFTip", "UBack", "Back",  "LBack", "LHip", "RHip", "LKne",
    "RKne",    "LAnk",  "RAnk",  "LFoot", "RFoot", "LToe",  "RToe"};

constexpr int index(Joint j) {
  return static_cast<int>(j);
}
constexpr std::string_view name(Joint j) {
  return kJointNames[static_cast<size_t>(j)];
}
std::optional<Joint> joint_from_name(std::string_view name);

struct Bone {
  std::string_view name;  // thesis Table 6.7 name
  Joint parent;           // towards the chest
  Joint child;
  double stature_ratio;  // bone length / stature (Table 6.7, the corrected ratios)
};

// Rooted at Chest; parents precede children.
inline constexpr std::array<Bone, kNumBones> kBones = {{
    {"Lower neck", Joint::Chest, Joint::Neck, 0.054},
    {"Upper neck", Joint::Neck, Joint::Head, 0.055},
    {"Head", Joint::Head, Joint::HeadTop, 0.055},
    {"Shoulder", Joint::Chest, Joint::LSho, 0.111},
    {"Shoulder", Joint::Chest, Joint::RSho, 0.111},
    {"Upper arm", Joint::LSho, Joint::LElb, 0.162},
    {"Upper arm", Joint::RSho, Joint::RElb, 0.162},
    {"Lower arm", Joint::LElb, Joint::LHand, 0.158},
    {"Lower arm", Joint::RElb, Joint::RHand, 0.158},
    {"Hand", Joint::LHand, Joint::LFTip, 0.038},
    {"Hand", Joint::RHand, Joint::RFTip, 0.038},
    {"Thorax", Joint::Chest, Joint::UBack, 0.065},
    {"Upper spine", Joint::UBack, Joint::Back, 0.065},
    {"Lower spine", Joint::Back, Joint::LBack, 0.065},
    {"Hip", Joint::LBack, Joint::LHip, 0.079},
    {"Hip", Joint::LBack, Joint::RHip, 0.079},
    {"Thigh", Joint::LHip, Joint::LKne, 0.224},
    {"Thigh", Joint::RHip, Joint::RKne, 0.224},
    {"Lower leg", Joint::LKne, Joint::LAnk, 0.239},
    {"Lower leg", Joint::RKne, Joint::RAnk, 0.239},
    {"Foot", Joint::LAnk, Joint::LFoot, 0.066},
    {"Foot", Joint::RAnk, Joint::RFoot, 0.066},
    {"Toe", Joint::LFoot, Joint::LToe, 0.033},
    {"Toe", Joint::RFoot, Joint::RToe, 0.033},
}};

// The index in kBones of the bone that ends at `child`: every joint but the root, Chest, has
// exactly one (-1 for Chest).
constexpr int bone_to(Joint child) {
  for (size_t b = 0; b < kBones.size(); ++b)
    if (kBones[b].child == child) return static_cast<int>(b);
  return -1;
}

// Extremities for the extremity error: head, hands and feet (the thesis' 46.8 mm figure scores
// hands and feet; hullpose-eval reports that subset too).
inline constexpr std::array<Joint, 5> kExtremities = {Joint::HeadTop, Joint::LHand, Joint::RHand,
                                                      Joint::LFoot, Joint::RFoot};

// The joint's mirror image (LSho <-> RSho); central joints map to themselves.
Joint mirror(Joint j);

}  // namespace hullpose
