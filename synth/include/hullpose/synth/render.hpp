#pragma once
// Exact silhouettes by ray casting: a pixel belongs to the person iff the viewing ray through
// its centre hits one of the avatar's primitives. Rays come from a per-camera map of
// undistorted normalised coordinates, so lens distortion is honoured exactly; only pixels
// inside each primitive's projected bounding box are visited.
//
// Hand-written rather than OpenCV drawing: cv::ellipse/fillPoly approximate conics by
// polygons and know nothing of lens distortion; this is the analytic projection (the mask is
// right to the pixel-centre sampling, i.e. within 0.5 px of the true outline).
#include <opencv2/core.hpp>
#include <vector>

#include "hullpose/common/camera.hpp"
#include "hullpose/synth/avatar.hpp"

namespace hullpose::synth {

class ViewRenderer {
 public:
  explicit ViewRenderer(const CameraModel& camera);
  const CameraModel& camera() const { return camera_; }

  // 255 where the person is, 0 elsewhere; `mask` is (re)allocated only if its size differs.
  void render_mask(const std::vector<Primitive>& primitives, cv::Mat& mask);

  // For colour rendering: per pixel the nearest primitive's material (255 = none, CV_8UC1) and
  // how squarely the surface faces the camera (0..1, CV_32FC1), plus the exact mask.
  void render_layers(const std::vector<Primitive>& primitives, cv::Mat& mask, cv::Mat& material,
                     cv::Mat& facing);

  // Unit viewing ray of a pixel in the camera frame (from the precomputed map).
  cv::Vec3f ray(int u, int v) const;

 private:
  struct Prepared;  // a primitive in camera coordinates, with its pixel bounding box
  bool prepare(const Primitive& p, Prepared& out) const;
  template <bool kLayers>
  void raster(const std::vector<Primitive>& primitives, cv::Mat& mask, cv::Mat* material,
              cv::Mat* facing);

  CameraModel camera_;
  cv::Mat rays_;   // CV_32FC2: undistorted normalised (x, y) of every pixel centre
  cv::Mat depth_;  // CV_32FC1 scratch for render_layers
};

}  // namespace hullpose::synth
