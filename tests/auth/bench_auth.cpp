// Cost of authentication per message (issue 19 goal: sign + verify <= 5 us at p99): the sender's
// sign() plus the receiver's verify() of one real LCM-encoded message, timed one message at a
// time so that the percentiles are those of single messages. Counters: p50_us / p99_us of
// sign + verify, sign_p99_us, verify_p99_us, message_bytes.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <hullpose_msg/silhouette_t.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <vector>

#include "hullpose/auth/message_auth.hpp"

namespace {

using hullpose::auth::kTrailerSize;

std::vector<uint8_t> encoded_silhouette(size_t payload) {
  hullpose_msg::silhouette_t m{};
  m.rig_id = "rigA";
  m.payload.assign(payload, 0x5a);
  m.payload_size = static_cast<int32_t>(payload);
  std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

std::vector<uint8_t> encoded_skeleton() {
  hullpose_msg::skeleton_t m{};
  m.rig_id = "rigA";
  m.num_joints = 25;
  m.joint_name.assign(25, "LeftUpLeg");
  m.position.assign(25, {1.f, 2.f, 3.f});
  m.confidence.assign(25, 1.f);
  std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

std::vector<uint8_t> encoded_trigger() {
  hullpose_msg::trigger_t m{};
  m.rig_id = "rigA";
  std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

double pct(std::vector<double>& v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

void sign_verify(benchmark::State& state, std::vector<uint8_t> message, const char* channel) {
  std::array<uint8_t, hullpose::auth::RigKey::kSize> raw{};
  raw.fill(7);
  const hullpose::auth::RigKey key(raw);
  hullpose::auth::Signer signer(key);
  hullpose::auth::Verifier verifier(key, {.max_skew_us = 0});
  const size_t n = message.size();
  message.resize(n + kTrailerSize);
  std::vector<double> total, sign, verify;
  const size_t cap = 1'000'000;
  total.reserve(cap);
  sign.reserve(cap);
  verify.reserve(cap);
  int64_t now = 1'700'000'000'000'000;
  using clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const auto t0 = clock::now();
    signer.sign(channel, message.data(), n, ++now, message.data() + n);
    const auto t1 = clock::now();
    const auto r = verifier.verify(channel, message.data(), message.size(), now);
    const auto t2 = clock::now();
    if (r.verdict != hullpose::auth::Verdict::kOk) state.SkipWithError("verify failed");
    if (total.size() < cap) {
      sign.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
      verify.push_back(std::chrono::duration<double, std::micro>(t2 - t1).count());
      total.push_back(std::chrono::duration<double, std::micro>(t2 - t0).count());
    }
  }
  state.counters["p50_us"] = pct(total, 0.5);
  state.counters["p99_us"] = pct(total, 0.99);
  state.counters["sign_p99_us"] = pct(sign, 0.99);
  state.counters["verify_p99_us"] = pct(verify, 0.99);
  state.counters["message_bytes"] = static_cast<double>(n);
}

// 3 KB: the median encoded human silhouette at 800x600 (bench_codec); 16 KB: a large one.
BENCHMARK_CAPTURE(sign_verify, silhouette_3k, encoded_silhouette(3000), "SILHOUETTE")
    ->Name("auth/sign_verify/silhouette_3k")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(sign_verify, silhouette_16k, encoded_silhouette(16000), "SILHOUETTE")
    ->Name("auth/sign_verify/silhouette_16k")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(sign_verify, skeleton, encoded_skeleton(), "SKELETON")
    ->Name("auth/sign_verify/skeleton")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(sign_verify, trigger, encoded_trigger(), "TRIGGER")
    ->Name("auth/sign_verify/trigger")
    ->Unit(benchmark::kMicrosecond);

}  // namespace
