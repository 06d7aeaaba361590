#pragma once
// Binary silhouette <-> bytes, small enough for one LCM datagram (docs/silhouette-codec.md).
//
// Payload v1 (little-endian):
//   "HS" | u8 version=1 | u8 flags=0 | u16 width | u16 height |
//   u16 roi_x | u16 roi_y | u16 roi_w | u16 roi_h | u32 run_count | run_count x LEB128 varint
// The runs cover the ROI row-major, alternating background/foreground, starting with
// background (which may be 0 long); they sum to roi_w * roi_h exactly. An empty mask has an
// empty ROI and no runs. The ROI is the foreground's bounding box.
//
// The decoder is fed untrusted bytes from the network: every size is checked against the
// payload and against the limits before anything is written, and it never throws; it returns
// a CodecError that the caller counts as a drop.
#include <cstddef>
#include <cstdint>
#include <opencv2/core/mat.hpp>
#include <span>
#include <vector>

namespace hullpose {

struct PixelRoi {
  int x = 0, y = 0, width = 0, height = 0;
  bool operator==(const PixelRoi&) const = default;
};

enum class CodecError {
  kNone = 0,
  kTruncatedHeader,
  kBadMagic,
  kUnsupportedVersion,
  kBadFlags,
  kImageTooLarge,
  kEmptyImage,
  kRoiOutsideImage,
  kTooManyRuns,
  kTruncatedRuns,
  kBadVarint,
  kRunsOverflowRoi,
  kRunsUnderfillRoi,
  kTrailingBytes,
};
const char* to_string(CodecError error);

struct SilhouetteHeader {
  int width = 0, height = 0;
  PixelRoi roi;
  uint32_t run_count = 0;
};

struct DecodeLimits {
  int max_width = 8192;
  int max_height = 8192;
};

// Reuses its scratch buffers: after the first frame of a given size, encode() allocates
// nothing as long as `out` keeps its capacity.
class SilhouetteEncoder {
 public:
  // mask: CV_8UC1, any non-zero value is foreground, at most 65535 px on a side.
  // Replaces the contents of `out`. Returns the ROI written into the header.
  PixelRoi encode(const cv::Mat& mask, std::vector<uint8_t>& out);

 private:
  std::vector<uint32_t> segments_;  // (row, x_begin, x_end) triples of foreground runs
};

// Parses and checks the fixed header only.
CodecError decode_silhouette_header(std::span<const uint8_t> payload, const DecodeLimits& limits,
                                    SilhouetteHeader& header);

// Decodes into `mask` (CV_8UC1, 255 = foreground), reallocating it only when the size
// changes. On error `mask` contents are unspecified but its size is valid or empty.
CodecError decode_silhouette(std::span<const uint8_t> payload, const DecodeLimits& limits,
                             cv::Mat& mask, SilhouetteHeader* header = nullptr);

}  // namespace hullpose
