#pragma once
// Authenticated LCM messages (docs/messages.md, "Authentication"). A publisher appends a
// 56-byte trailer to every LCM-encoded message; lcm-gen decoders and tools such as lcm-spy and
// lcm-logger ignore bytes after the message, so the .lcm types are unchanged. Trailer layout
// (big-endian, offsets in bytes):
//
//    0  u32  key id       RigKey::id() of the signing key
//    4  16B  sender       random per Signer (per publishing process)
//   20  u64  counter      1, 2, 3, ... per sender, over all its channels
//   28  i64  sent_utime   sender's clock at publish, microseconds since the epoch
//   36  16B  tag          Poly1305 over u32 len(channel) | channel | message | trailer[0, 36)
//   52  4B   "HPA1"       magic
//
// The Poly1305 key of each message is the first 32 bytes of the XChaCha20 key stream of the rig
// key under the nonce sender|counter (the construction of NaCl's secretbox and of libsodium's
// XChaCha20-Poly1305): a fresh one-time key per message, so the tag is a MAC under the rig key.
// Chosen over crypto_auth (HMAC-SHA-512-256) and keyed BLAKE2b because it is 3-7x faster on
// silhouette-sized messages (3 KB: Poly1305 ~1.3 us, BLAKE2b ~4 us, HMAC ~9 us on this
// machine), measured by bench_auth, and the budget is 5 us per message at p99. The Poly1305 is
// OpenSSL's: the same tag as libsodium's, about 2x faster from a few KB up (AVX2/AVX-512, NEON),
// which keeps silhouettes of larger sensors inside the budget (bench_auth auth/tag/*).
// AES-256-GCM as a MAC (GMAC: the message as additional data) is ~2x faster again on x86 with
// AES-NI (bench_auth auth/tag/stream/*), but not on camera boards without ARM's crypto
// extensions (Raspberry Pi 4), which sign the largest messages, so a rig could not use it
// throughout.
//
// The receiver (Verifier) drops, and names the reason of, a message that has no trailer, one
// signed with another key (another rig), one whose tag does not verify (forged or corrupted),
// one whose counter that sender already used or that lies behind its window (replayed,
// duplicated), and one whose sent_utime is further than max_skew from the receiver's clock
// (a replay of a recording from a sender the receiver no longer remembers).
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string_view>
#include <vector>

#include "hullpose/auth/rig_key.hpp"

namespace hullpose::auth {

inline constexpr size_t kTrailerSize = 56;
using SenderId = std::array<uint8_t, 16>;

enum class Verdict : uint8_t { kOk, kMissing, kWrongKey, kBadMac, kStale, kReplayed };
// The drop counter name of a verdict: "auth_missing", "auth_wrong_key", "auth_bad_mac",
// "auth_stale", "auth_replayed" ("ok" for kOk).
std::string_view counter_name(Verdict v);

// Signs messages of one publishing process. Thread-safe (the counter is atomic).
class Signer {
 public:
  explicit Signer(const RigKey& key);  // random sender id
  Signer(const RigKey& key, const SenderId& sender);

  // Writes the kTrailerSize trailer of `message` on `channel` to `trailer`.
  void sign(std::string_view channel, const void* message, size_t size, int64_t now_utime,
            uint8_t* trailer);
  const SenderId& sender() const { return sender_; }

 private:
  RigKey key_;
  SenderId sender_;
  std::atomic<uint64_t> counter_{0};
};

struct VerifierConfig {
  // |receiver clock - sent_utime| allowed; 0 turns the time check off (replaying a recorded
  // take into a live host, rigs whose clocks are not synchronised).
  int64_t max_skew_us = 30'000'000;
  // Senders whose replay windows are remembered; the least recently heard is forgotten first.
  size_t max_senders = 64;
};

struct Verified {
  Verdict verdict;
  size_t message_size;  // bytes before the trailer (valid when verdict is kOk)
};

// Checks messages on every channel of one receiving process. Thread-safe. Allocates only at
// construction: a flood of forged messages never reaches the sender table.
class Verifier {
 public:
  static constexpr uint64_t kWindow = 256;  // counters behind the newest still accepted once

  explicit Verifier(const RigKey& key, VerifierConfig config = {});
  Verified verify(std::string_view channel, const void* data, size_t size, int64_t now_utime);

 private:
  struct Window {
    SenderId sender{};
    uint64_t top = 0;                           // newest counter accepted
    std::array<uint64_t, kWindow / 64> seen{};  // bit d: counter top - d accepted
    uint64_t last_used = 0;
  };
  bool accept(const SenderId& sender, uint64_t counter);

  RigKey key_;
  VerifierConfig config_;
  std::mutex mutex_;
  std::vector<Window> windows_;
  uint64_t tick_ = 0;
};

// Without a key a receiver accepts everything: the message size without a trailer if `data`
// ends in one, `size` otherwise.
size_t strip_trailer(const void* data, size_t size);

}  // namespace hullpose::auth
