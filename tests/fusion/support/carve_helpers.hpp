#pragma once
// Carving with a throw-away report: the fast path and the brute-force reference.
#include <opencv2/core/mat.hpp>
#include <vector>

#include "hullpose/carve/carver.hpp"

namespace hullpose::fusion::testing {

inline BitGrid fast(carve::Carver& c, const std::vector<cv::Mat>& views,
                    carve::CarveReport* out = nullptr) {
  BitGrid hull;
  carve::CarveReport report;
  c.carve(views, hull, report);
  if (out) *out = report;
  return hull;
}
inline BitGrid brute(const carve::Carver& c, const std::vector<cv::Mat>& views) {
  BitGrid hull;
  carve::CarveReport report;
  c.carve_brute_force(views, hull, report);
  return hull;
}

}  // namespace hullpose::fusion::testing
