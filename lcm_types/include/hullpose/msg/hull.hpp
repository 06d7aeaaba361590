#pragma once
// The coarse carved hull of hull_t (channel HULL) and its payload: the occupancy as a binary
// image (nx wide, ny*nz high; voxel (x,y,z) at column x, row y + ny*z) in the silhouette codec,
// whose run lengths along x suit a body in a mostly empty volume (a 64³ grid of a person: about
// 1 KB instead of 32 KB of bits) and whose decoder is already hardened for network input.
//
// The fusion host fills a CoarseHull (fusion_host/service/hull_publisher.hpp) and sends it with
// to_message; a view gets it back with from_message, which checks every field (sizes, geometry,
// encoding, the payload and its voxel count) before trusting any: a hostile hull_t is an error
// to count, never a throw or an allocation beyond MAX_DIM³.
#include <array>
#include <cstdint>
#include <hullpose_msg/hull_t.hpp>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "hullpose/common/silhouette_codec.hpp"

namespace hullpose::msg {

struct CoarseHull {
  int64_t utime = 0;
  int64_t trigger_seq = -1;
  std::array<int, 3> dims{};  // nx, ny, nz, each 1..hull_t::MAX_DIM
  std::array<float, 3> origin_mm{};
  float voxel_mm = 0;
  float carved_voxel_mm = 0;
  // CV_8UC1, dims[0] columns x dims[1]*dims[2] rows, non-zero = occupied.
  cv::Mat occupancy;
  int num_occupied = 0;

  bool occupied(int x, int y, int z) const {
    return occupancy.at<uint8_t>(y + dims[1] * z, x) != 0;
  }
};

enum class HullError {
  kNone = 0,
  kBadDims,      // a side outside 1..MAX_DIM
  kBadGeometry,  // origin or voxel sizes not finite, not positive or absurd
  kBadEncoding,  // unknown encoding
  kBadPayload,   // the silhouette codec refused it (or its size is not nx x ny*nz)
  kBadCount,     // num_occupied is not what the payload holds
};
const char* to_string(HullError error);

// Fills `msg` from `hull` (hull.occupancy and num_occupied must agree); reuses msg's payload.
void to_message(const CoarseHull& hull, const std::string& rig_id, SilhouetteEncoder& encoder,
                hullpose_msg::hull_t& msg);

// Checks every field of `msg` (already through wire::decode) and fills `out`; on an error `out`
// is unspecified but its occupancy is at most MAX_DIM x MAX_DIM² pixels.
HullError from_message(const hullpose_msg::hull_t& msg, CoarseHull& out);

}  // namespace hullpose::msg
