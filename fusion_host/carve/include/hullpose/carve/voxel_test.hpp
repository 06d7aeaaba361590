#pragma once
// The per-voxel carving test, shared verbatim by the CPU carver (fast path and brute-force
// reference) and the CUDA backend (fusion_host/gpu), so the CPU tests exercise the arithmetic
// the GPU runs. Plain doubles and ints: no Eigen in device code.
//
// Bit-identical results on both sides need the same IEEE operations in the same order: the
// multiply-adds are explicit fma() calls, hullpose_carve is compiled with -ffp-contract=off and
// the CUDA sources with --fmad=false, so neither compiler fuses anything else on its own and
// changes a rounding at a pixel border.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "hullpose/common/host_device.hpp"

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
HULLPOSE_HD inline bool project_to_pixel(const CameraParams& c, double wx, double wy, double wz,
                                         int& px, int& py) {
  // Explicit fused multiply-adds: one rounding each, the same on both compilers, and as fast as
  // the contraction the compiler would otherwise choose on its own (x86 FMA, CUDA DFMA).
  const double X = fma(c.r[0], wx, fma(c.r[1], wy, fma(c.r[2], wz, c.t[0])));
  const double Y = fma(c.r[3], wx, fma(c.r[4], wy, fma(c.r[5], wz, c.t[1])));
  const double Z = fma(c.r[6], wx, fma(c.r[7], wy, fma(c.r[8], wz, c.t[2])));
  if (!(Z > 0)) return false;
  const double x = X / Z, y = Y / Z;
  const double r2 = fma(x, x, y * y);
  const double radial = fma(r2, fma(r2, fma(r2, c.k3, c.k2), c.k1), 1.0);
  const double xd = fma(x, radial, fma(2 * c.p1 * x, y, c.p2 * fma(2 * x, x, r2)));
  const double yd = fma(y, radial, fma(c.p1, fma(2 * y, y, r2), 2 * c.p2 * x * y));
  const double u = fma(c.fx, xd, c.cx), v = fma(c.fy, yd, c.cy);
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
  size_t stride = 0;                                   // bytes per row
  int box_x0 = 0, box_y0 = 0, box_x1 = 0, box_y1 = 0;  // [x0, x1) x [y0, y1)
};

// Does the voxel centre project onto foreground in this camera?
HULLPOSE_HD inline bool centre_hits(const CameraParams& c, const MaskView& m, double wx, double wy,
                                    double wz) {
  int px, py;
  return project_to_pixel(c, wx, wy, wz, px, py) && px >= m.box_x0 && px < m.box_x1 &&
         py >= m.box_y0 && py < m.box_y1 &&
         m.data[static_cast<size_t>(py) * m.stride + static_cast<size_t>(px)] != 0;
}

// The carving rule: kept iff it misses in at most k of the n cameras (all but k).
HULLPOSE_HD inline bool voxel_kept(const CameraParams* cams, const MaskView* masks, int n, int k,
                                   double wx, double wy, double wz) {
  int misses = 0;
  for (int i = 0; i < n; ++i)
    if (!centre_hits(cams[i], masks[i], wx, wy, wz) && ++misses > k) return false;
  return true;
}

}  // namespace hullpose::carve
