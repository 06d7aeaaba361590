#pragma once
// The per-voxel carving test, shared verbatim by the CPU carver (fast path and brute-force
// reference) and the CUDA backend (fusion_host/gpu), so the CPU tests exercise the arithmetic
// the GPU runs. Plain doubles and ints: no Eigen in device code.
//
// Bit-identical results on both sides need the same IEEE operations in the same order:
// hullpose_carve is compiled with -ffp-contract=off and the CUDA sources with --fmad=false, so
// neither compiler fuses a multiply-add and changes a rounding at a pixel border.
#include <cstddef>
#include <cstdint>

#ifndef HULLPOSE_HD
#ifdef __CUDACC__
#define HULLPOSE_HD __host__ __device__
#else
#define HULLPOSE_HD
#endif
#endif

namespace hullpose::carve {

// One camera: world (mm) -> pixel, pinhole + OpenCV k1 k2 p1 p2 k3 (CameraModel's model).
struct CameraParams {
  double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major world -> camera rotation
  double t[3] = {0, 0, 0};
  double fx = 0, fy = 0, cx = 0, cy = 0, k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  int width = 0, height = 0;
};

// The pixel whose centre is nearest to the projected point (halves round up). False if the
// point is not in front of the camera or the pixel is outside the image.
HULLPOSE_HD inline bool project_to_pixel(const CameraParams& c, double wx, double wy, double wz, int& px, int& py) {
  const double X = c.r[0] * wx + c.r[1] * wy + c.r[2] * wz + c.t[0];
  const double Y = c.r[3] * wx + c.r[4] * wy + c.r[5] * wz + c.t[1];
  const double Z = c.r[6] * wx + c.r[7] * wy + c.r[8] * wz + c.t[2];
  if (!(Z > 0)) return false;
  const double x = X / Z, y = Y / Z;
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  const double xd = x * radial + 2 * c.p1 * x * y + c.p2 * (r2 + 2 * x * x);
  const double yd = y * radial + c.p1 * (r2 + 2 * y * y) + 2 * c.p2 * x * y;
  const double u = c.fx * xd + c.cx, v = c.fy * yd + c.cy;
  // Compare as doubles first: a far-off point must not overflow the int conversion.
  if (!(u >= -0.5 && v >= -0.5 && u < c.width - 0.5 && v < c.height - 0.5)) return false;
  px = static_cast<int>(u + 0.5);
  py = static_cast<int>(v + 0.5);
  return true;
}

// A silhouette as the test reads it: pixels outside `box` are background whatever the buffer
// holds there (the GPU uploads only the foreground box).
struct MaskView {
  const uint8_t* data = nullptr;
  size_t stride = 0;  // bytes per row
  int box_x0 = 0, box_y0 = 0, box_x1 = 0, box_y1 = 0;  // [x0, x1) x [y0, y1)
};

// Does the voxel centre project onto foreground in this camera?
HULLPOSE_HD inline bool centre_hits(const CameraParams& c, const MaskView& m, double wx, double wy, double wz) {
  int px, py;
  return project_to_pixel(c, wx, wy, wz, px, py) && px >= m.box_x0 && px < m.box_x1 && py >= m.box_y0 &&
         py < m.box_y1 && m.data[static_cast<size_t>(py) * m.stride + static_cast<size_t>(px)] != 0;
}

// The carving rule: kept iff it misses in at most k of the n cameras (all but k).
HULLPOSE_HD inline bool voxel_kept(const CameraParams* cams, const MaskView* masks, int n, int k, double wx, double wy,
                                   double wz) {
  int misses = 0;
  for (int i = 0; i < n; ++i)
    if (!centre_hits(cams[i], masks[i], wx, wy, wz) && ++misses > k) return false;
  return true;
}

}  // namespace hullpose::carve
