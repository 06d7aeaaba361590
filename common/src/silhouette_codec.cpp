#include "hullpose/common/silhouette_codec.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "hullpose/common/check.hpp"

// Hand-written rather than cv::findNonZero + cv::compress-style helpers: OpenCV has no
// run-length codec, and the word-at-a-time run search below is what makes encode+decode run
// at several GB/s of mask pixels on one core (make bench: codec/*).

namespace hullpose {
namespace {

constexpr uint8_t kMagic0 = 'H', kMagic1 = 'S', kVersion = 1;
constexpr size_t kHeaderSize = 20;
constexpr uint64_t kOnes = 0x0101010101010101ull;
constexpr uint64_t kHighs = 0x8080808080808080ull;

uint64_t load64(const uint8_t* p) {
  uint64_t w;
  std::memcpy(&w, p, 8);
  return w;
}

// First x in [x, end) whose byte is non-zero (searching background) or zero (searching
// foreground); `end` if none.
int find_change(const uint8_t* row, int x, int end, bool in_foreground) {
  while (x + 8 <= end) {
    const uint64_t w = load64(row + x);
    // Bytes that end the current run: non-zero bytes for background, zero bytes for
    // foreground (the classic has-zero-byte test; its lowest flagged byte is exact).
    const uint64_t flags = in_foreground ? ((w - kOnes) & ~w & kHighs) : w;
    if (flags) return x + std::countr_zero(flags) / 8;
    x += 8;
  }
  while (x < end && (row[x] != 0) == in_foreground) ++x;
  return x;
}

void put_u16(uint8_t* p, int v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
int get_u16(const uint8_t* p) {
  return p[0] | (p[1] << 8);
}
uint32_t get_u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}

size_t put_varint(uint8_t* p, uint32_t v) {
  size_t n = 0;
  while (v >= 0x80) {
    p[n++] = static_cast<uint8_t>(v | 0x80);
    v >>= 7;
  }
  p[n++] = static_cast<uint8_t>(v);
  return n;
}

// Reads one LEB128 value of at most 32 bits; false on truncation or overlong/oversized input.
bool get_varint(const uint8_t*& p, const uint8_t* end, uint32_t& value) {
  uint64_t v = 0;
  for (int shift = 0; shift < 35; shift += 7) {
    if (p == end) return false;
    const uint8_t byte = *p++;
    v |= static_cast<uint64_t>(byte & 0x7f) << shift;
    if (!(byte & 0x80)) {
      if (v > 0xffffffffull) return false;
      value = static_cast<uint32_t>(v);
      return true;
    }
  }
  return false;
}

}  // namespace

const char* to_string(CodecError error) {
  switch (error) {
    case CodecError::kNone:
      return "ok";
    case CodecError::kTruncatedHeader:
      return "payload shorter than the 20-byte header";
    case CodecError::kBadMagic:
      return "bad magic (not a hullpose silhouette)";
    case CodecError::kUnsupportedVersion:
      return "unsupported codec version";
    case CodecError::kBadFlags:
      return "unknown flags set";
    case CodecError::kImageTooLarge:
      return "image size exceeds the decoder's limit";
    case CodecError::kEmptyImage:
      return "image width or height is zero";
    case CodecError::kRoiOutsideImage:
      return "ROI lies outside the image";
    case CodecError::kTooManyRuns:
      return "run count exceeds what the ROI and payload can hold";
    case CodecError::kTruncatedRuns:
      return "payload ends before the declared runs";
    case CodecError::kBadVarint:
      return "malformed run length";
    case CodecError::kRunsOverflowRoi:
      return "runs extend past the ROI";
    case CodecError::kRunsUnderfillRoi:
      return "runs do not cover the ROI";
    case CodecError::kTrailingBytes:
      return "bytes after the last run";
  }
  return "unknown codec error";
}

PixelRoi SilhouetteEncoder::encode(const cv::Mat& mask, std::vector<uint8_t>& out) {
  HULLPOSE_THROW_UNLESS(mask.type() == CV_8UC1, "silhouette encoder: mask must be CV_8UC1");
  HULLPOSE_THROW_UNLESS(mask.cols <= 0xffff && mask.rows <= 0xffff,
                        "silhouette encoder: mask larger than 65535 px on a side");
  segments_.clear();
  int x0 = mask.cols, x1 = 0, y0 = -1, y1 = -1;
  for (int y = 0; y < mask.rows; ++y) {
    const uint8_t* row = mask.ptr<uint8_t>(y);
    int x = find_change(row, 0, mask.cols, false);
    while (x < mask.cols) {
      const int end = find_change(row, x, mask.cols, true);
      segments_.insert(segments_.end(), {static_cast<uint32_t>(y), static_cast<uint32_t>(x),
                                         static_cast<uint32_t>(end)});
      x0 = std::min(x0, x);
      x1 = std::max(x1, end);
      if (y0 < 0) y0 = y;
      y1 = y + 1;
      x = find_change(row, end, mask.cols, false);
    }
  }
  PixelRoi roi;
  if (y0 >= 0) roi = {x0, y0, x1 - x0, y1 - y0};

  // Worst case: two runs per segment plus the trailing one, 5 bytes each.
  const size_t nseg = segments_.size() / 3;
  out.resize(kHeaderSize + (2 * nseg + 1) * 5);
  uint8_t* p = out.data();
  p[0] = kMagic0;
  p[1] = kMagic1;
  p[2] = kVersion;
  p[3] = 0;
  put_u16(p + 4, mask.cols);
  put_u16(p + 6, mask.rows);
  put_u16(p + 8, roi.x);
  put_u16(p + 10, roi.y);
  put_u16(p + 12, roi.width);
  put_u16(p + 14, roi.height);
  size_t n = kHeaderSize;
  uint32_t runs = 0;
  if (nseg > 0) {
    const auto w = static_cast<uint64_t>(roi.width);
    uint64_t pos = 0;  // linear position inside the ROI
    // Segments of consecutive rows that touch in the ROI's linear order (a ROI one pixel wide, or
    // a row's run ending at the ROI's right edge and the next row's starting at its left edge)
    // join into one foreground run: an empty background run between them would break the
    // decoder's bound of area + 2 runs (found by fuzz_silhouette_decoder: a vertical line).
    uint64_t fg_begin = 0, fg_len = 0;  // the foreground run not yet written
    auto write_run = [&] {
      n += put_varint(p + n, static_cast<uint32_t>(fg_begin - pos));
      n += put_varint(p + n, static_cast<uint32_t>(fg_len));
      pos = fg_begin + fg_len;
      runs += 2;
    };
    for (size_t i = 0; i < nseg; ++i) {
      const uint64_t begin = (segments_[3 * i] - static_cast<uint32_t>(roi.y)) * w +
                             (segments_[3 * i + 1] - static_cast<uint32_t>(roi.x));
      const uint64_t len = segments_[3 * i + 2] - segments_[3 * i + 1];
      if (fg_len > 0 && begin == fg_begin + fg_len) {
        fg_len += len;
        continue;
      }
      if (fg_len > 0) write_run();
      fg_begin = begin;
      fg_len = len;
    }
    write_run();
    n += put_varint(p + n, static_cast<uint32_t>(w * static_cast<uint64_t>(roi.height) - pos));
    ++runs;
  }
  put_u32(p + 16, runs);
  out.resize(n);
  return roi;
}

CodecError decode_silhouette_header(std::span<const uint8_t> payload, const DecodeLimits& limits,
                                    SilhouetteHeader& h) {
  if (payload.size() < kHeaderSize) return CodecError::kTruncatedHeader;
  const uint8_t* p = payload.data();
  if (p[0] != kMagic0 || p[1] != kMagic1) return CodecError::kBadMagic;
  if (p[2] != kVersion) return CodecError::kUnsupportedVersion;
  if (p[3] != 0) return CodecError::kBadFlags;
  h.width = get_u16(p + 4);
  h.height = get_u16(p + 6);
  h.roi = {get_u16(p + 8), get_u16(p + 10), get_u16(p + 12), get_u16(p + 14)};
  h.run_count = get_u32(p + 16);
  if (h.width == 0 || h.height == 0) return CodecError::kEmptyImage;
  if (h.width > limits.max_width || h.height > limits.max_height) return CodecError::kImageTooLarge;
  if (h.roi.x + h.roi.width > h.width || h.roi.y + h.roi.height > h.height)
    return CodecError::kRoiOutsideImage;
  const uint64_t area = static_cast<uint64_t>(h.roi.width) * static_cast<uint64_t>(h.roi.height);
  // Runs alternate background/foreground; only the first and the last may be empty, so a
  // valid ROI holds at most area + 2 runs, and each run takes at least one byte.
  if (h.run_count > area + 2 || h.run_count > payload.size() - kHeaderSize)
    return CodecError::kTooManyRuns;
  if (area == 0 && h.run_count != 0) return CodecError::kTooManyRuns;
  return CodecError::kNone;
}

CodecError decode_silhouette(std::span<const uint8_t> payload, const DecodeLimits& limits,
                             cv::Mat& mask, SilhouetteHeader* header_out) {
  SilhouetteHeader h;
  if (const CodecError e = decode_silhouette_header(payload, limits, h); e != CodecError::kNone)
    return e;
  mask.create(h.height, h.width, CV_8UC1);
  mask = cv::Scalar::all(0);  // unlike setTo(), allocates nothing (no InputArray temporary)
  const uint8_t* p = payload.data() + kHeaderSize;
  const uint8_t* const end = payload.data() + payload.size();
  const uint64_t w = static_cast<uint64_t>(h.roi.width);
  const uint64_t area = w * static_cast<uint64_t>(h.roi.height);
  uint64_t pos = 0;
  for (uint32_t i = 0; i < h.run_count; ++i) {
    uint32_t len = 0;
    if (!get_varint(p, end, len))
      return p == end ? CodecError::kTruncatedRuns : CodecError::kBadVarint;
    if (len > area - pos) return CodecError::kRunsOverflowRoi;
    if (i & 1) {  // foreground run, possibly wrapping over ROI rows
      uint64_t remaining = len, at = pos;
      while (remaining > 0) {
        const uint64_t row = at / w, col = at % w;
        const uint64_t chunk = std::min<uint64_t>(remaining, w - col);
        std::memset(mask.ptr<uint8_t>(h.roi.y + static_cast<int>(row)) + h.roi.x + col, 255, chunk);
        at += chunk;
        remaining -= chunk;
      }
    }
    pos += len;
  }
  if (pos != area) return CodecError::kRunsUnderfillRoi;
  if (p != end) return CodecError::kTrailingBytes;
  if (header_out) *header_out = h;
  return CodecError::kNone;
}

}  // namespace hullpose
