#include "hullpose/pose/lag_smoother.hpp"

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/pose/body_model.hpp"
#include "hullpose/pose/model_fit.hpp"

namespace hullpose::pose {

int parse_lag_frames(const std::string& value, const char* what) {
  const long long n = cli::parse_integer(what, value);
  HULLPOSE_THROW_UNLESS(n == 0 || n == 1,
                        what << ": expected 0 (publish each frame as soon as it is "
                                "fitted) or 1 (one frame late, smoothed), got "
                             << value);
  return static_cast<int>(n);
}

LagSmoother::LagSmoother(LagParams params) : params_(params) {}

bool LagSmoother::near(const Frame& a, const Frame& b) const {
  return a.present && a.valid && b.valid &&
         mean_displacement(a.pose, b.pose) <= params_.jump_mean_mm;
}

const JointPositions* LagSmoother::push(const JointPositions& pose, bool valid, bool follows) {
  const Frame next{pose, valid, true};
  const JointPositions* out = nullptr;
  if (held_.present) {
    out_ = held_.pose;
    if (follows && near(before_, held_) && near(held_, next)) {
      const double w = params_.weight;
      for (int j = 0; j < kNumJoints; ++j)
        out_[j] = w * before_.pose[j] + (1 - 2 * w) * held_.pose[j] + w * next.pose[j];
      // The mean shortens bones that turn (a chord of their arc): they get the frame's own back.
      for (int b = 0; b < kNumBones; ++b)
        lengths_[b] =
            (held_.pose[index(kBones[b].child)] - held_.pose[index(kBones[b].parent)]).norm();
      impose_bone_lengths(out_, lengths_);
    }
    out = &out_;
    before_ = held_;
  }
  before_.present = before_.present && follows;
  held_ = next;
  return out;
}

const JointPositions* LagSmoother::release() {
  if (!held_.present) return nullptr;
  out_ = held_.pose;
  before_ = held_;
  held_.present = false;
  return &out_;
}

}  // namespace hullpose::pose
