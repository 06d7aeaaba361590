#pragma once
// Test and benchmark scenes for the fusion core until the synthetic rig (tools/synth) lands:
// a thesis-like rig (7 cameras around the volume + 1 in the ceiling) and a human-like body made
// of capsules, rendered to silhouettes or voxelised directly.
#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <random>
#include <vector>

#include "hullpose/common/rig.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion/bit_grid.hpp"

namespace hullpose::fusion::testing {

struct Capsule {
  Eigen::Vector3d a, b;  // segment ends (mm)
  double radius;         // mm
};

// 7 cameras on a circle (radius 4 m, 2 m high) + 1 looking down from 4.5 m, capture volume
// 2.4 x 2.4 x 2.2 m, mild radial distortion. `cameras` <= 8 takes the first ones.
Rig thesis_like_rig(int width = 800, int height = 600, int cameras = 8);

// A standing person (~1.75 m) made of capsules; `phase` in [0, 1) moves arms and legs, `yaw`
// turns the body about z, `offset` moves it on the floor.
std::vector<Capsule> human_capsules(double phase, double yaw = 0,
                                    const Eigen::Vector2d& offset = {0, 0});

// Silhouette (CV_8UC1, 255 = person) of the capsules in one camera (convex hulls of projected
// sphere samples; an approximation of the true outline, which is all a test input needs).
cv::Mat render_silhouette(const CameraModel& camera, const std::vector<Capsule>& body);
std::vector<cv::Mat> render_views(const Rig& rig, const std::vector<Capsule>& body);

// Voxels whose centre lies inside a capsule.
BitGrid voxelise(const VoxelGridSpec& grid, const std::vector<Capsule>& body);

}  // namespace hullpose::fusion::testing
