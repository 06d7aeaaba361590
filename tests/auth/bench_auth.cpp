// Cost of authentication per message (issue 19 goal: sign + verify <= 5 us at p99): the sender's
// sign() plus the receiver's verify() of one real LCM-encoded message, timed one message at a
// time so that the percentiles are those of single messages. Counters: p50_us / p99_us of
// sign + verify, sign_p99_us, verify_p99_us, message_bytes.
//
// auth/sign_verify/stream/*: the messages a rig really sends, in the order it sends them: per
// trigger instant one TRIGGER, one SILHOUETTE per camera (the masks encoded by the camera node's
// codec into the silhouette_t it publishes) and one SKELETON. Two rigs: the real crane capture
// (8 cameras, 1600x1200, ../shared/data/real/vlasic-crane) and the synthetic thesis rig (8
// cameras, 800x600, CMU 55_01). Percentiles over all messages and over the silhouettes alone
// (time_stream says which). auth/tag/*: one side's tag, ours (OpenSSL's Poly1305) against the
// same tag computed by libsodium (what common/auth used before) and against AES-256-GCM as a
// MAC (the construction considered instead), over the crane stream and a 16 KB message.
#include <benchmark/benchmark.h>
#include <sodium.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <hullpose_msg/silhouette_t.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "../bench/thesis8_masks.hpp"
#include "hullpose/auth/message_auth.hpp"
#include "hullpose/common/joints.hpp"
#include "hullpose/common/silhouette_codec.hpp"
#include "reference_tag.hpp"

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

// Fixed sizes: 3 KB is about the largest real silhouette (crane, 1600x1200: <= 3.7 KB); 16 KB
// is four times that, a bound for larger sensors.
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

struct Message {
  const char* channel;
  std::vector<uint8_t> bytes;
};

template <class T>
std::vector<uint8_t> encoded(const T& m) {
  std::vector<uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

// One trigger instant of a rig: what the master, every camera node and the fusion host publish.
void append_instant(const std::vector<cv::Mat>& masks, int64_t seq, std::vector<Message>& out) {
  const int64_t utime = 1'700'000'000'000'000 + seq * 33'333;
  hullpose_msg::trigger_t trig{};
  trig.utime = utime;
  trig.rig_id = "crane";
  trig.seq = seq;
  trig.period_us = 33'333;
  trig.pulse_width_us = 1000;
  out.push_back({"TRIGGER", encoded(trig)});
  hullpose::SilhouetteEncoder enc;
  for (size_t c = 0; c < masks.size(); ++c) {
    // The fields camera_node's SilhouettePublisher fills (publisher.cpp).
    hullpose_msg::silhouette_t m{};
    const hullpose::PixelRoi roi = enc.encode(masks[c], m.payload);
    m.utime = utime;
    m.rig_id = trig.rig_id;
    m.camera_id = static_cast<int32_t>(c + 1);
    m.trigger_seq = seq;
    m.capture_utime = utime + 120;
    m.width = masks[c].cols;
    m.height = masks[c].rows;
    m.roi_x = roi.x;
    m.roi_y = roi.y;
    m.roi_width = roi.width;
    m.roi_height = roi.height;
    m.encoding = hullpose_msg::silhouette_t::ENCODING_RLE_V1;
    m.payload_size = static_cast<int32_t>(m.payload.size());
    m.node_done_utime = utime + 9000;
    out.push_back({"SILHOUETTE", encoded(m)});
  }
  hullpose_msg::skeleton_t sk{};
  sk.utime = utime;
  sk.rig_id = trig.rig_id;
  sk.trigger_seq = seq;
  sk.num_joints = hullpose::kNumJoints;
  for (const auto& name : hullpose::kJointNames) sk.joint_name.emplace_back(name);
  sk.position.assign(hullpose::kNumJoints, {100.f, 900.f, 1200.f});
  sk.confidence.assign(hullpose::kNumJoints, 1.f);
  sk.valid = true;
  sk.cameras_used_mask = (int64_t{1} << masks.size()) - 1;
  sk.num_cameras_used = static_cast<int32_t>(masks.size());
  out.push_back({"SKELETON", encoded(sk)});
}

// The crane's silhouettes as the importer reads them (grey above 127 is the person).
std::vector<Message> crane_stream() {
  const std::filesystem::path dir =
      std::filesystem::path(HULLPOSE_SHARED_DIR) / "data/real/vlasic-crane/silhouettes";
  std::vector<Message> out;
  for (int f = 0;; ++f) {
    std::vector<cv::Mat> masks;
    for (int cam = 1; cam <= 8; ++cam) {
      char name[64];
      std::snprintf(name, sizeof name, "camera%d_%04d.png", cam, f);
      const cv::Mat grey = cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
      if (grey.empty()) return out;
      masks.emplace_back();
      cv::threshold(grey, masks.back(), 127, 255, cv::THRESH_BINARY);
    }
    append_instant(masks, f, out);
  }
}

std::vector<Message> thesis8_stream() {
  const hullpose::bench::Thesis8Masks t = hullpose::bench::render_thesis8_55_01();
  std::vector<Message> out;
  const auto cams = static_cast<size_t>(t.cameras);
  for (size_t f = 0; cams > 0 && (f + 1) * cams <= t.masks.size(); ++f)
    append_instant({t.masks.begin() + static_cast<std::ptrdiff_t>(f * cams),
                    t.masks.begin() + static_cast<std::ptrdiff_t>((f + 1) * cams)},
                   static_cast<int64_t>(f), out);
  return out;
}

// Runs `op` on the stream's messages one at a time, in order, round and round, and reports its
// time per message: over all runs (p50_us, p99_us: what a loaded machine adds, preemptions
// included) and per message as the fastest of its runs (msg_p50_us, msg_p99_us: the cost of
// that message itself, without the other processes of this shared machine).
template <class Op>
void time_stream(benchmark::State& state, const std::vector<Message>& messages, Op op) {
  if (messages.empty()) {
    state.SkipWithError("no messages (is ../shared there?)");
    return;
  }
  size_t largest = 0;
  for (const auto& m : messages) largest = std::max(largest, m.bytes.size());
  std::vector<uint8_t> buf(largest + kTrailerSize);
  std::vector<double> total, silhouette, fastest(messages.size(), 1e300);
  const size_t cap = 1'000'000;
  total.reserve(cap);
  silhouette.reserve(cap);
  size_t i = 0;
  using clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const size_t k = i++ % messages.size();
    const Message& m = messages[k];
    std::memcpy(buf.data(), m.bytes.data(), m.bytes.size());  // as the publisher encoded it
    const auto t0 = clock::now();
    const bool ok = op(m, buf.data());
    const auto t1 = clock::now();
    if (!ok) state.SkipWithError("verify failed");
    const double us = std::chrono::duration<double, std::micro>(t1 - t0).count();
    fastest[k] = std::min(fastest[k], us);
    if (total.size() < cap) {
      total.push_back(us);
      if (std::string_view(m.channel) == "SILHOUETTE") silhouette.push_back(us);
    }
  }
  std::vector<double> sizes, silhouette_sizes, msg_fastest, silhouette_fastest;
  for (size_t k = 0; k < messages.size(); ++k) {
    sizes.push_back(static_cast<double>(messages[k].bytes.size()));
    const bool timed = k < i;  // Google Benchmark's first trials run a few iterations only
    if (timed) msg_fastest.push_back(fastest[k]);
    if (std::string_view(messages[k].channel) == "SILHOUETTE") {
      silhouette_sizes.push_back(sizes.back());
      if (timed) silhouette_fastest.push_back(fastest[k]);
    }
  }
  state.counters["p50_us"] = pct(total, 0.5);
  state.counters["p99_us"] = pct(total, 0.99);
  state.counters["silhouette_p99_us"] = pct(silhouette, 0.99);
  state.counters["msg_p50_us"] = pct(msg_fastest, 0.5);
  state.counters["msg_p99_us"] = pct(msg_fastest, 0.99);
  state.counters["msg_max_us"] = pct(msg_fastest, 1.0);
  state.counters["silhouette_msg_p99_us"] = pct(silhouette_fastest, 0.99);
  state.counters["runs_per_message"] = static_cast<double>(i / messages.size());
  state.counters["messages"] = static_cast<double>(messages.size());
  state.counters["message_bytes_p50"] = pct(sizes, 0.5);
  state.counters["silhouette_bytes_p50"] = pct(silhouette_sizes, 0.5);
  state.counters["silhouette_bytes_p99"] = pct(silhouette_sizes, 0.99);
  state.counters["message_bytes_max"] = static_cast<double>(largest);
}

hullpose::auth::RigKey bench_key() {
  std::array<uint8_t, hullpose::auth::RigKey::kSize> raw{};
  raw.fill(7);
  return hullpose::auth::RigKey(raw);
}

// What authentication adds to a message: the sender's sign() and the receiver's verify().
void sign_verify_stream(benchmark::State& state, const std::vector<Message>& (*stream)()) {
  const hullpose::auth::RigKey key = bench_key();
  hullpose::auth::Signer signer(key);
  hullpose::auth::Verifier verifier(key, {.max_skew_us = 0});
  int64_t now = 1'700'000'000'000'000;
  time_stream(state, stream(), [&](const Message& m, uint8_t* buf) {
    const size_t n = m.bytes.size();
    signer.sign(m.channel, buf, n, ++now, buf + n);
    return verifier.verify(m.channel, buf, n + kTrailerSize, now).verdict ==
           hullpose::auth::Verdict::kOk;
  });
}

// One side's tag: ours (sign), the same tag by libsodium's Poly1305 (common/auth before issue
// 19's measurement; tests/auth/reference_tag.hpp), and the construction considered instead:
// AES-256-GCM with an empty plaintext and the message as additional data (GMAC), key schedule
// precomputed as a receiver would per sender.
void tag_stream_ours(benchmark::State& state, const std::vector<Message>& (*stream)()) {
  hullpose::auth::Signer signer(bench_key());
  time_stream(state, stream(), [&](const Message& m, uint8_t* buf) {
    signer.sign(m.channel, buf, m.bytes.size(), 1, buf + m.bytes.size());
    return true;
  });
}

void tag_stream_libsodium(benchmark::State& state, const std::vector<Message>& (*stream)()) {
  const hullpose::auth::RigKey key = bench_key();
  time_stream(state, stream(), [&](const Message& m, uint8_t* buf) {
    const auto tag = hullpose::auth::testing::reference_tag(key, m.channel, buf, m.bytes.size(),
                                                            buf + m.bytes.size());
    benchmark::DoNotOptimize(tag);
    return true;
  });
}

void tag_stream_aes256gcm(benchmark::State& state, const std::vector<Message>& (*stream)()) {
  if (sodium_init() < 0 || crypto_aead_aes256gcm_is_available() == 0) {
    state.SkipWithError("no AES-NI/PCLMUL: libsodium has no AES-256-GCM on this CPU");
    return;
  }
  crypto_aead_aes256gcm_state ctx;
  crypto_aead_aes256gcm_beforenm(&ctx, bench_key().bytes().data());
  uint64_t counter = 0;
  time_stream(state, stream(), [&](const Message& m, uint8_t* buf) {
    uint8_t nonce[crypto_aead_aes256gcm_NPUBBYTES] = {};
    std::memcpy(nonce, &++counter, sizeof counter);
    unsigned long long tag_len = 0;
    uint8_t no_ciphertext[1];
    crypto_aead_aes256gcm_encrypt_detached_afternm(no_ciphertext, buf + m.bytes.size(), &tag_len,
                                                   nullptr, 0, buf, m.bytes.size(), nullptr, nonce,
                                                   &ctx);
    return tag_len == crypto_aead_aes256gcm_ABYTES;
  });
}

const std::vector<Message>& crane() {
  static const std::vector<Message> s = crane_stream();
  return s;
}
const std::vector<Message>& thesis8() {
  static const std::vector<Message> s = thesis8_stream();
  return s;
}
const std::vector<Message>& silhouette_16k() {
  static const std::vector<Message> s = {{"SILHOUETTE", encoded_silhouette(16000)}};
  return s;
}

BENCHMARK_CAPTURE(sign_verify_stream, crane, &crane)
    ->Name("auth/sign_verify/stream/crane_8x1600x1200")
    ->MinTime(0.3)  // dozens of runs over the stream: msg_* are per-message minima
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(sign_verify_stream, thesis8, &thesis8)
    ->Name("auth/sign_verify/stream/thesis8_55_01_8x800x600")
    ->MinTime(0.3)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(tag_stream_ours, crane, &crane)
    ->Name("auth/tag/stream/crane_8x1600x1200/xchacha20_poly1305")
    ->MinTime(0.3)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(tag_stream_libsodium, crane, &crane)
    ->Name("auth/tag/stream/crane_8x1600x1200/xchacha20_poly1305_libsodium")
    ->MinTime(0.3)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(tag_stream_aes256gcm, crane, &crane)
    ->Name("auth/tag/stream/crane_8x1600x1200/aes256gcm_gmac")
    ->MinTime(0.3)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(tag_stream_ours, silhouette_16k, &silhouette_16k)
    ->Name("auth/tag/silhouette_16k/xchacha20_poly1305")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(tag_stream_libsodium, silhouette_16k, &silhouette_16k)
    ->Name("auth/tag/silhouette_16k/xchacha20_poly1305_libsodium")
    ->Unit(benchmark::kMicrosecond);

}  // namespace
