// Silhouette codec throughput (goal: encode+decode >= 2 GB/s of mask pixels on one core).
// Counter mask_GBps = mask pixels (bytes) per second through encode + decode.
#include <benchmark/benchmark.h>

#include <opencv2/imgproc.hpp>

#include "hullpose/common/silhouette_codec.hpp"

namespace {

cv::Mat person_mask(int w, int h) {
  cv::Mat m(h, w, CV_8UC1, cv::Scalar(0));
  const cv::Scalar fg(255);
  cv::circle(m, {w / 2, h / 5}, h / 16, fg, -1);
  cv::ellipse(m, {w / 2, h / 2 - h / 12}, {w / 18, h / 6}, 0, 0, 360, fg, -1);
  cv::line(m, {w / 2, h / 3}, {w / 2 - w / 6, h / 2}, fg, w / 60);
  cv::line(m, {w / 2, h / 3}, {w / 2 + w / 7, h / 4}, fg, w / 60);
  cv::line(m, {w / 2 - 10, h / 2 + h / 12}, {w / 2 - w / 14, h - h / 12}, fg, w / 45);
  cv::line(m, {w / 2 + 10, h / 2 + h / 12}, {w / 2 + w / 20, h - h / 12}, fg, w / 45);
  return m;
}

void codec_roundtrip(benchmark::State& state) {
  const cv::Mat mask =
      person_mask(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  hullpose::SilhouetteEncoder enc;
  std::vector<uint8_t> bytes;
  cv::Mat out;
  for (auto _ : state) {
    enc.encode(mask, bytes);
    if (hullpose::decode_silhouette(bytes, {}, out) != hullpose::CodecError::kNone)
      state.SkipWithError("decode failed");
    benchmark::DoNotOptimize(out.data);
  }
  state.counters["mask_GBps"] = benchmark::Counter(static_cast<double>(mask.total()) * 1e-9,
                                                   benchmark::Counter::kIsIterationInvariantRate);
  state.counters["encoded_bytes"] = static_cast<double>(bytes.size());
}
BENCHMARK(codec_roundtrip)
    ->Name("codec/roundtrip_person")
    ->Args({800, 600})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(codec_roundtrip)
    ->Name("codec/roundtrip_person")
    ->Args({640, 480})
    ->Unit(benchmark::kMillisecond);

}  // namespace

// Human silhouettes from the synthetic rig (thesis8_masks.hpp). encoded_bytes_median is the
// issue's <= 3 KB goal.
#include <algorithm>

#include "thesis8_masks.hpp"

namespace {

struct HumanMasks {
  std::vector<cv::Mat> masks;
  double median_bytes = 0, max_bytes = 0;
  HumanMasks() : masks(hullpose::bench::render_thesis8_55_01().masks) {
    hullpose::SilhouetteEncoder enc;
    std::vector<uint8_t> bytes;
    std::vector<double> sizes;
    for (const auto& m : masks) {
      enc.encode(m, bytes);
      sizes.push_back(static_cast<double>(bytes.size()));
    }
    if (sizes.empty()) return;
    std::sort(sizes.begin(), sizes.end());
    median_bytes = sizes[sizes.size() / 2];
    max_bytes = sizes[sizes.size() - 1];
  }
};

void codec_human_55_01(benchmark::State& state) {
  static const HumanMasks human;
  hullpose::SilhouetteEncoder enc;
  std::vector<uint8_t> bytes;
  cv::Mat out;
  size_t i = 0;
  for (auto _ : state) {
    if (human.masks.empty()) {
      state.SkipWithError("no masks rendered");
      break;
    }
    const cv::Mat& mask = human.masks[i++ % human.masks.size()];
    enc.encode(mask, bytes);
    if (hullpose::decode_silhouette(bytes, {}, out) != hullpose::CodecError::kNone)
      state.SkipWithError("decode failed");
    benchmark::DoNotOptimize(out.data);
  }
  state.counters["mask_GBps"] =
      benchmark::Counter(800.0 * 600.0 * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["encoded_bytes_median"] = human.median_bytes;
  state.counters["encoded_bytes_max"] = human.max_bytes;
  state.counters["masks"] = static_cast<double>(human.masks.size());
}
BENCHMARK(codec_human_55_01)
    ->Name("codec/roundtrip_human_55_01_thesis8/800x600")
    ->Unit(benchmark::kMillisecond);

}  // namespace
