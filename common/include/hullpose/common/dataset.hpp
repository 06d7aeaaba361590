#pragma once
// Datasets on disk (docs/conventions.md): the rig, per-camera frames, ground truth and
// metadata, and the estimate files the fusion host writes and hullpose-eval reads.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "hullpose/common/joints.hpp"

namespace hullpose {

using JointPositions = std::array<Eigen::Vector3d, kNumJoints>;  // mm, rig frame

struct DatasetMeta {
  static constexpr int kFormat = 1;
  std::string motion;  // built-in motion name or BVH file name
  int frames = 0;
  double fps = 30;
  uint64_t seed = 0;
  int64_t start_utime = 0;  // trigger time of frame 0
  double stature_mm = 0;    // ground-truth stature of the subject
  std::vector<int> camera_ids;
  std::string noise;  // free-form description of injected faults ("" = none)
};

// One frame of ground truth or of an estimate.
struct PoseRecord {
  int frame = 0;
  int64_t utime = 0;      // ground truth only
  bool valid = true;      // estimates only
  int reason = 0;         // estimates only: skeleton_t REASON_*
  int model_version = 0;  // estimates only: skeleton_t model_version (0 in files without it)
  JointPositions joints{};
};

class DatasetPaths {
 public:
  explicit DatasetPaths(std::filesystem::path root) : root_(std::move(root)) {}
  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path rig() const { return root_ / "rig.yaml"; }
  std::filesystem::path meta() const { return root_ / "meta.json"; }
  std::filesystem::path ground_truth() const { return root_ / "ground_truth.csv"; }
  std::filesystem::path camera_dir(int camera_id) const;
  std::filesystem::path mask(int camera_id, int frame) const;
  std::filesystem::path rgb(int camera_id, int frame) const;
  std::filesystem::path background(int camera_id, int index) const;

 private:
  std::filesystem::path root_;
};

// All readers throw hullpose::Error naming the file and line on bad content. Each parse_* reads
// the file's text instead, `path` naming it in errors (the fuzz targets use them).
void write_meta(const std::filesystem::path& path, const DatasetMeta& meta);
DatasetMeta read_meta(const std::filesystem::path& path);
DatasetMeta parse_meta(std::string_view text, const std::filesystem::path& path);

void write_ground_truth(const std::filesystem::path& path, const std::vector<PoseRecord>& frames);
std::vector<PoseRecord> read_ground_truth(const std::filesystem::path& path);
std::vector<PoseRecord> parse_ground_truth(const std::string& text,
                                           const std::filesystem::path& path);

// Streams an estimate file frame by frame (the fusion host writes as it goes).
class EstimateWriter {
 public:
  explicit EstimateWriter(const std::filesystem::path& path);
  void write(const PoseRecord& record);
  void flush() { out_.flush(); }

 private:
  std::filesystem::path path_;
  std::ofstream out_;
};
std::vector<PoseRecord> read_estimates(const std::filesystem::path& path);
std::vector<PoseRecord> parse_estimates(const std::string& text, const std::filesystem::path& path);

}  // namespace hullpose
