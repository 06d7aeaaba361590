#pragma once
// Motions: the 25 joints of common/joints.hpp as a function of time, in mm in the rig frame
// (z up, floor at z = 0). Two sources: CMU BVH clips (three naming schemes, see
// synth/README.md for the joint map) and built-in procedural motions that need no files.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hullpose/common/dataset.hpp"
#include "hullpose/synth/bvh.hpp"

namespace hullpose::synth {

class Motion {
 public:
  virtual ~Motion() = default;
  const std::string& name() const { return name_; }
  // Ground-truth stature: height of HeadTop above the floor in the upright rest pose (mm).
  double stature_mm() const { return stature_mm_; }
  // Length of the clip in seconds; infinite for procedural motions (they loop).
  virtual double duration_s() const = 0;
  // Joint positions at time t (seconds from the start); clamps to the clip.
  virtual void sample(double t_s, JointPositions& out) const = 0;

  // Frames of a clip at `fps` whose time k / fps lies inside it: floor(duration * fps)
  // (CMU 55_01: 1807 frames at 120 fps -> 451 at 30 fps). Throws for an endless motion.
  int frame_count(double fps) const;

 protected:
  Motion(std::string name, double stature_mm) : name_(std::move(name)), stature_mm_(stature_mm) {}

 private:
  std::string name_;
  double stature_mm_;
};

struct MotionOptions {
  Eigen::Vector3d centre_mm = Eigen::Vector3d::Zero();  // floor point the subject moves around
  double build = 1.0;  // girth multiplier (sets how far the soles reach below the joints)
  // Built-in motions only:
  double stature_mm = 1750;  // body size
  double speed = 1.0;        // tempo multiplier (1 = natural pace of the motion)
  double stride_mm = 0;      // walk/run step length; 0 = the motion's default for the stature
  // BVH only: millimetres per file unit; 0 = by naming scheme (CMU units for A/B, metres for C).
  double bvh_mm_per_unit = 0;
};

enum class BvhScheme { A, B, C };
const char* scheme_name(BvhScheme s);
// Which naming scheme a clip uses; throws naming the clip if none matches.
BvhScheme detect_scheme(const BvhClip& clip);

// Millimetres per CMU unit: the ASF length unit is 1/0.45 inch.
inline constexpr double kCmuUnitMm = 25.4 / 0.45;

std::unique_ptr<Motion> make_bvh_motion(const BvhClip& clip, const MotionOptions& options);
std::unique_ptr<Motion> load_bvh_motion(const std::filesystem::path& path,
                                        const MotionOptions& options);

// walk, run, jump, crouch, turn (pirouette), wave, tpose.
const std::vector<std::string>& builtin_motion_names();
std::unique_ptr<Motion> make_builtin_motion(const std::string& name, const MotionOptions& options);

// A path ending in .bvh (any case) is loaded, anything else must be a built-in name.
std::unique_ptr<Motion> make_motion(const std::string& spec, const MotionOptions& options);

}  // namespace hullpose::synth
