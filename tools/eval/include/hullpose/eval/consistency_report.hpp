#pragma once
// How hullpose-eval presents a ConsistencyResult (scoring without ground truth): one JSON
// object, a text table, and an HTML page with the figures and, for the chosen frames, every
// camera's view with the skeleton drawn over its colour frame (or its silhouette), because people
// judge a pose by looking at it.
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <ostream>
#include <vector>

#include "hullpose/common/dataset.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/eval/consistency.hpp"

namespace hullpose::eval {

void write_consistency_json(std::ostream& out, const ConsistencyResult& result);
void write_consistency_table(std::ostream& out, const ConsistencyResult& result,
                             const std::string& dataset, const std::string& estimate);

// One camera's picture of a frame: the colour frame (cam<ID>/rgb_*.png) if the dataset has it,
// else the silhouette in grey; the silhouette's outline; the bones (left side blue, right side
// red, centre green) and the bone points outside the silhouette as yellow dots.
cv::Mat draw_view(const CameraModel& camera, const cv::Mat& mask, const cv::Mat& colour,
                  const JointPositions& joints, double tolerance_px, double sample_step_mm);

// Writes DIR/report.html and DIR/frame<F>_cam<ID>.png for result.picture_frames; returns the
// page's path.
std::filesystem::path write_consistency_report(const std::filesystem::path& dir,
                                               const std::filesystem::path& dataset,
                                               const std::string& estimate,
                                               const std::vector<PoseRecord>& estimates,
                                               const ConsistencyResult& result,
                                               const ConsistencyOptions& options);

}  // namespace hullpose::eval
