// Fuzz target: the silhouette decoder must reject or decode any byte string without crashing,
// reading out of bounds, or allocating beyond its limits; whatever it decodes re-encodes to a
// mask equal to the decoded one.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "hullpose/common/silhouette_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static cv::Mat mask, again;
  static std::vector<uint8_t> bytes;
  static hullpose::SilhouetteEncoder encoder;
  const hullpose::DecodeLimits limits{1024, 1024};
  if (hullpose::decode_silhouette({data, size}, limits, mask) != hullpose::CodecError::kNone)
    return 0;
  encoder.encode(mask, bytes);
  if (hullpose::decode_silhouette(bytes, limits, again) != hullpose::CodecError::kNone)
    std::abort();
  if (cv::countNonZero(mask != again) != 0) std::abort();
  return 0;
}

// Valid payloads for the replay test and the libFuzzer seed corpus.
std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  cv::Mat mask(40, 50, CV_8UC1, cv::Scalar(0));
  cv::circle(mask, {25, 20}, 12, cv::Scalar(255), -1);
  std::vector<uint8_t> a, b;
  hullpose::SilhouetteEncoder().encode(mask, a);
  mask(cv::Rect(30, 0, 20, 40)).setTo(255);
  hullpose::SilhouetteEncoder().encode(mask, b);
  return {a, b};
}
