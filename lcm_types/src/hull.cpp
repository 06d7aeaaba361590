#include "hullpose/msg/hull.hpp"

#include <cmath>
#include <opencv2/core.hpp>

namespace hullpose::msg {

const char* to_string(HullError error) {
  switch (error) {
    case HullError::kNone:
      return "none";
    case HullError::kBadDims:
      return "bad_dims";
    case HullError::kBadGeometry:
      return "bad_geometry";
    case HullError::kBadEncoding:
      return "bad_encoding";
    case HullError::kBadPayload:
      return "bad_payload";
    case HullError::kBadCount:
      return "bad_count";
  }
  return "unknown";
}

void to_message(const CoarseHull& hull, const std::string& rig_id, SilhouetteEncoder& encoder,
                hullpose_msg::hull_t& msg) {
  msg.utime = hull.utime;
  msg.rig_id = rig_id;
  msg.trigger_seq = hull.trigger_seq;
  msg.nx = hull.dims[0];
  msg.ny = hull.dims[1];
  msg.nz = hull.dims[2];
  for (int i = 0; i < 3; ++i) msg.origin_mm[i] = hull.origin_mm[static_cast<size_t>(i)];
  msg.voxel_mm = hull.voxel_mm;
  msg.carved_voxel_mm = hull.carved_voxel_mm;
  msg.num_occupied = hull.num_occupied;
  msg.encoding = hullpose_msg::hull_t::ENCODING_RLE_V1;
  encoder.encode(hull.occupancy, msg.payload);
  msg.payload_size = static_cast<int32_t>(msg.payload.size());
}

HullError from_message(const hullpose_msg::hull_t& msg, CoarseHull& out) {
  constexpr int kMax = hullpose_msg::hull_t::MAX_DIM;
  for (const int32_t n : {msg.nx, msg.ny, msg.nz})
    if (n < 1 || n > kMax) return HullError::kBadDims;
  // A rig is metres across: a coordinate beyond 1 km or a voxel beyond 10 m is no hull.
  const auto sane = [](float v, float limit) { return std::isfinite(v) && std::fabs(v) <= limit; };
  for (const float o : msg.origin_mm)
    if (!sane(o, 1e6f)) return HullError::kBadGeometry;
  if (!sane(msg.voxel_mm, 1e4f) || msg.voxel_mm <= 0 || !sane(msg.carved_voxel_mm, 1e4f) ||
      msg.carved_voxel_mm <= 0 || msg.carved_voxel_mm > msg.voxel_mm)
    return HullError::kBadGeometry;
  if (msg.encoding != hullpose_msg::hull_t::ENCODING_RLE_V1) return HullError::kBadEncoding;
  DecodeLimits limits;
  limits.max_width = kMax;
  limits.max_height = kMax * kMax;
  SilhouetteHeader header;
  if (decode_silhouette(msg.payload, limits, out.occupancy, &header) != CodecError::kNone ||
      header.width != msg.nx || header.height != msg.ny * msg.nz)
    return HullError::kBadPayload;
  if (cv::countNonZero(out.occupancy) != msg.num_occupied) return HullError::kBadCount;
  out.utime = msg.utime;
  out.trigger_seq = msg.trigger_seq;
  out.dims = {msg.nx, msg.ny, msg.nz};
  out.origin_mm = {msg.origin_mm[0], msg.origin_mm[1], msg.origin_mm[2]};
  out.voxel_mm = msg.voxel_mm;
  out.carved_voxel_mm = msg.carved_voxel_mm;
  out.num_occupied = msg.num_occupied;
  return HullError::kNone;
}

}  // namespace hullpose::msg
