// JSON, text-table and per-frame CSV output of an EvalResult.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "format.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/eval/consistency.hpp"
#include "hullpose/eval/report.hpp"
#include "hullpose/msg/reasons.hpp"

namespace hullpose::eval {
namespace {

using Json = nlohmann::ordered_json;

// Three decimals, as the table prints them; null when not finite (nothing to score).
Json num(double v) {
  return std::isfinite(v) ? Json(std::round(v * 1000.0) / 1000.0) : Json(nullptr);
}

void box_fields(Json& o, const std::string& prefix, const BoxStats& b) {
  o[prefix + "_std_mm"] = num(b.std);
  o[prefix + "_median_mm"] = num(b.median);
  o[prefix + "_max_mm"] = num(b.max);
}

Json vec3(const Eigen::Vector3d& v) {
  return Json{{"x", num(v.x())}, {"y", num(v.y())}, {"z", num(v.z())}};
}

}  // namespace

void write_json(std::ostream& out, const EvalResult& r) {
  Json o;
  o["frames"] = r.frames;
  o["scored_frames"] = r.scored_frames;
  o["invalid_frames"] = r.invalid_frames;
  o["missing_frames"] = r.missing_frames;
  o["out_of_volume_frames"] = r.out_of_volume_frames;
  o["out_of_volume_invalid"] = r.out_of_volume_invalid;
  o["out_of_volume_mpjpe_mm"] = num(r.out_of_volume_mpjpe_mm);
  Json reasons = Json::object();
  for (const auto& [code, count] : r.invalid_reasons) reasons[msg::reason_name(code)] = count;
  o["invalid_reasons"] = reasons;
  o["valid_pct"] = num(r.valid_pct);
  o["mpjpe_mm"] = num(r.all_joints.mean);
  box_fields(o, "mpjpe", r.all_joints);
  o["extremity_mpjpe_mm"] = num(r.extremities.mean);
  box_fields(o, "extremity", r.extremities);
  o["hands_feet_mpjpe_mm"] = num(r.hands_feet.mean);
  box_fields(o, "hands_feet", r.hands_feet);
  o["frame_mpjpe_std_mm"] = num(r.frame_mean.std);
  o["frame_mpjpe_median_mm"] = num(r.frame_mean.median);
  o["frame_mpjpe_max_mm"] = num(r.frame_mean.max);
  o["worst_frame"] = r.scored_frames > 0 ? Json(r.worst_frame) : Json(nullptr);
  o["frame_hands_feet_std_mm"] = num(r.frame_hands_feet.std);
  o["frame_hands_feet_median_mm"] = num(r.frame_hands_feet.median);
  o["pck50_pct"] = num(r.pck50_pct);
  o["pck100_pct"] = num(r.pck100_pct);
  o["pck50_valid_pct"] = num(r.pck50_valid_pct);
  o["pck100_valid_pct"] = num(r.pck100_valid_pct);
  o["lr_correct_pct"] = num(r.lr_correct_pct);
  o["lr_arms_correct_pct"] = num(r.lr_arms_correct_pct);
  o["lr_legs_correct_pct"] = num(r.lr_legs_correct_pct);
  o["stature_mm"] = num(r.stature_meta_mm);
  o["stature_gt_mm"] = num(r.stature_gt_mm);
  o["stature_est_mm"] = num(r.stature_est_mm);
  o["stature_est_std_mm"] = num(r.stature_est_std_mm);
  o["stature_error_mm"] = num(r.stature_error_mm);
  o["stature_error_meta_mm"] = num(r.stature_error_meta_mm);
  Json bones = Json::object();
  for (int b = 0; b < kNumBones; ++b)
    bones[bone_key(b)] = num(r.bone_length_error_pct[static_cast<size_t>(b)]);
  o["bone_length_error_pct"] = bones;
  o["bone_length_error_median_abs_pct"] = num(r.bone_length_error_median_abs_pct);
  o["axis_abs_mm"] = vec3(r.axis_abs_mm);
  o["axis_bias_mm"] = vec3(r.axis_bias_mm);
  Json joints = Json::object();
  for (size_t j = 0; j < kNumJoints; ++j) {
    const BoxStats& b = r.per_joint[j];
    joints[kJointNames[j]] =
        Json{{"mean_mm", num(b.mean)},       {"std_mm", num(b.std)}, {"median_mm", num(b.median)},
             {"q1_mm", num(b.q1)},           {"q3_mm", num(b.q3)},   {"max_mm", num(b.max)},
             {"outliers", b.outliers.size()}};
  }
  o["per_joint"] = joints;
  out << o.dump() << '\n';
}

void write_table(std::ostream& out, const EvalResult& r, const ReportSource& source) {
  char line[160];
  auto row = [&](const char* label, const std::string& value) {
    std::snprintf(line, sizeof line, "  %-34s %s\n", label, value.c_str());
    out << line;
  };
  auto mm = [](double v) { return fixed(v, 1, "-") + " mm"; };
  auto pc = [](double v) { return fixed(v, 1, "-") + " %"; };
  auto stats = [&](const BoxStats& b) {
    return fixed(b.mean, 1, "-") + " mm   (std " + fixed(b.std, 1, "-") + ", median " +
           fixed(b.median, 1, "-") + ", max " + fixed(b.max, 1, "-") + ")";
  };

  out << "hullpose-eval  " << source.estimate << "  vs  " << source.dataset;
  if (!source.motion.empty()) out << "  (" << source.motion << ")";
  out << "\n\nFrames\n";
  row("ground-truth frames (in the volume)", std::to_string(r.frames));
  row("scored (estimate valid)", std::to_string(r.scored_frames) + "   (" + pc(r.valid_pct) + ")");
  std::string invalid = std::to_string(r.invalid_frames);
  for (const auto& [code, count] : r.invalid_reasons)
    invalid += "   " + msg::reason_name(code) + "=" + std::to_string(count);
  row("invalid (estimate valid=0)", invalid);
  row("missing from the estimate file", std::to_string(r.missing_frames));
  row("true body outside the volume",
      std::to_string(r.out_of_volume_frames) + "   (flagged invalid " +
          std::to_string(r.out_of_volume_invalid) + ", scored at " + mm(r.out_of_volume_mpjpe_mm) +
          "; not counted above or below)");

  out << "\nJoint error over scored frames\n";
  row("all joints (MPJPE)", stats(r.all_joints));
  row("extremities (head, hands, feet)", stats(r.extremities));
  row("hands and feet (thesis Fig. 6.1)", stats(r.hands_feet));
  row("per-frame mean, all joints",
      stats(r.frame_mean) +
          (r.scored_frames > 0 ? "  worst frame " + std::to_string(r.worst_frame) : ""));
  row("per-frame mean, hands and feet", stats(r.frame_hands_feet));
  row("mean |error| x / y / z", fixed(r.axis_abs_mm.x(), 1, "-") + " / " +
                                    fixed(r.axis_abs_mm.y(), 1, "-") + " / " +
                                    fixed(r.axis_abs_mm.z(), 1, "-") + " mm");
  row("mean signed error x / y / z", fixed(r.axis_bias_mm.x(), 1, "-") + " / " +
                                         fixed(r.axis_bias_mm.y(), 1, "-") + " / " +
                                         fixed(r.axis_bias_mm.z(), 1, "-") + " mm");
  row("PCK@50 mm / @100 mm, all frames", pc(r.pck50_pct) + " / " + pc(r.pck100_pct));
  row("PCK@50 mm / @100 mm, scored frames", pc(r.pck50_valid_pct) + " / " + pc(r.pck100_valid_pct));
  row("left/right correct (arms, legs)", pc(r.lr_correct_pct) + "   (" + pc(r.lr_arms_correct_pct) +
                                             ", " + pc(r.lr_legs_correct_pct) + ")");

  out << "\nStature\n";
  row("true (meta.json)", mm(r.stature_meta_mm));
  row("of the ground-truth joints", mm(r.stature_gt_mm));
  row("of the estimated joints",
      mm(r.stature_est_mm) + "   (std " + fixed(r.stature_est_std_mm, 1, "-") + ")");
  row("error vs ground-truth joints", mm(r.stature_error_mm));
  row("error vs true stature", mm(r.stature_error_meta_mm));
  row("bone lengths, median |error|", pc(r.bone_length_error_median_abs_pct));

  out << "\nPer joint (mm)     mean      std   median       q1       q3      max  outliers\n";
  for (size_t j = 0; j < kNumJoints; ++j) {
    const BoxStats& b = r.per_joint[j];
    std::snprintf(line, sizeof line, "  %-12s %8s %8s %8s %8s %8s %8s  %8zu\n",
                  kJointNames[j].data(), fixed(b.mean, 1, "-").c_str(),
                  fixed(b.std, 1, "-").c_str(), fixed(b.median, 1, "-").c_str(),
                  fixed(b.q1, 1, "-").c_str(), fixed(b.q3, 1, "-").c_str(),
                  fixed(b.max, 1, "-").c_str(), b.outliers.size());
    out << line;
  }
}

void write_per_frame_csv(const std::filesystem::path& path, const EvalResult& r) {
  std::ofstream out(path);
  HULLPOSE_THROW_UNLESS(out, path.string() << ": cannot write");
  out << "frame,status,reason,mean_mm,extremity_mm,hands_feet_mm,abs_x_mm,abs_y_mm,abs_z_mm,"
         "bias_x_mm,bias_y_mm,bias_z_mm,lr_arms_correct,lr_legs_correct,stature_gt_mm,stature_est_"
         "mm,in_volume\n";
  for (const FrameResult& f : r.per_frame) {
    out << f.frame << ',' << to_string(f.status) << ','
        << (f.status == FrameStatus::Missing ? "" : msg::reason_name(f.reason));
    const bool scored = f.status == FrameStatus::Scored;
    for (double v :
         {f.mean_mm, f.extremity_mm, f.hands_feet_mm, f.axis_abs_mm.x(), f.axis_abs_mm.y(),
          f.axis_abs_mm.z(), f.axis_bias_mm.x(), f.axis_bias_mm.y(), f.axis_bias_mm.z()})
      out << ',' << fixed(v, 3, "");
    out << ',' << (scored ? (f.lr_arms_correct ? "1" : "0") : "") << ','
        << (scored ? (f.lr_legs_correct ? "1" : "0") : "") << ',' << fixed(f.stature_gt_mm, 3, "")
        << ',' << fixed(f.stature_est_mm, 3, "") << ',' << (f.in_volume ? '1' : '0') << '\n';
  }
  HULLPOSE_THROW_UNLESS(out, path.string() << ": write failed");
}

}  // namespace hullpose::eval
