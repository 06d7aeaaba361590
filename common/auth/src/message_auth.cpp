#include "hullpose/auth/message_auth.hpp"

#include <openssl/evp.h>
#include <sodium.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "hullpose/common/check.hpp"

namespace hullpose::auth {
namespace {

constexpr uint8_t kMagic[4] = {'H', 'P', 'A', '1'};
constexpr size_t kSignedHeader = 36;  // key id, sender, counter, sent_utime
constexpr size_t kTagOffset = 36;
constexpr size_t kMagicOffset = 52;

void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 3; i >= 0; --i, v >>= 8) p[i] = static_cast<uint8_t>(v);
}
void put_u64(uint8_t* p, uint64_t v) {
  for (int i = 7; i >= 0; --i, v >>= 8) p[i] = static_cast<uint8_t>(v);
}
uint32_t get_u32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v = (v << 8) | p[i];
  return v;
}
uint64_t get_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return v;
}

// Poly1305 is computed by OpenSSL, the rest of the construction by libsodium: Debian 12's
// libsodium (1.0.18) has only portable/SSE2 Poly1305 code, OpenSSL 3.0 has AVX2/AVX-512
// (x86-64) and NEON (arm64) code. Same bytes (test_auth checks them against libsodium's
// crypto_onetimeauth), about 2x faster on a 16 KB message (docs/perf-log.md, issue 19). The
// context is per thread because signers and verifiers are called from several threads; made
// once per thread, so signing allocates nothing per message.
struct MacContextFree {
  void operator()(EVP_MAC_CTX* c) const { EVP_MAC_CTX_free(c); }
};

EVP_MAC_CTX* poly1305_context() {
  static EVP_MAC* const mac = EVP_MAC_fetch(nullptr, "POLY1305", nullptr);
  HULLPOSE_THROW_UNLESS(mac != nullptr,
                        "auth: OpenSSL has no POLY1305 MAC (a provider configuration without it?)");
  thread_local const std::unique_ptr<EVP_MAC_CTX, MacContextFree> ctx(EVP_MAC_CTX_new(mac));
  HULLPOSE_THROW_UNLESS(ctx != nullptr, "auth: cannot create an OpenSSL POLY1305 context");
  return ctx.get();
}

// Poly1305 tag of one message under the one-time key derived from the rig key and the nonce
// sender|counter (trailer bytes 4..28).
void compute_tag(const RigKey& key, std::string_view channel, const uint8_t* message, size_t size,
                 const uint8_t* header, uint8_t* tag) {
  uint8_t one_time[crypto_onetimeauth_KEYBYTES];
  static_assert(crypto_stream_xchacha20_NONCEBYTES == 24);
  crypto_stream_xchacha20(one_time, sizeof one_time, header + 4, key.bytes().data());
  EVP_MAC_CTX* const ctx = poly1305_context();
  uint8_t len[4];
  put_u32(len, static_cast<uint32_t>(channel.size()));
  size_t tag_size = 0;
  const bool ok =
      EVP_MAC_init(ctx, one_time, sizeof one_time, nullptr) == 1 &&
      EVP_MAC_update(ctx, len, sizeof len) == 1 &&
      EVP_MAC_update(ctx, reinterpret_cast<const uint8_t*>(channel.data()), channel.size()) == 1 &&
      EVP_MAC_update(ctx, message, size) == 1 && EVP_MAC_update(ctx, header, kSignedHeader) == 1 &&
      EVP_MAC_final(ctx, tag, &tag_size, crypto_onetimeauth_BYTES) == 1 &&
      tag_size == crypto_onetimeauth_BYTES;
  sodium_memzero(one_time, sizeof one_time);
  HULLPOSE_THROW_UNLESS(ok, "auth: OpenSSL POLY1305 failed");
}

}  // namespace

std::string_view counter_name(Verdict v) {
  switch (v) {
    case Verdict::kOk:
      return "ok";
    case Verdict::kMissing:
      return "auth_missing";
    case Verdict::kWrongKey:
      return "auth_wrong_key";
    case Verdict::kBadMac:
      return "auth_bad_mac";
    case Verdict::kStale:
      return "auth_stale";
    case Verdict::kReplayed:
      return "auth_replayed";
  }
  return "auth_unknown";
}

Signer::Signer(const RigKey& key) : key_(key) {
  poly1305_context();  // a missing MAC is an error at start-up, not at the first message
  randombytes_buf(sender_.data(), sender_.size());
}

Signer::Signer(const RigKey& key, const SenderId& sender) : key_(key), sender_(sender) {
  poly1305_context();
}

void Signer::sign(std::string_view channel, const void* message, size_t size, int64_t now_utime,
                  uint8_t* trailer) {
  put_u32(trailer, key_.id());
  std::memcpy(trailer + 4, sender_.data(), sender_.size());
  put_u64(trailer + 20, counter_.fetch_add(1, std::memory_order_relaxed) + 1);
  put_u64(trailer + 28, static_cast<uint64_t>(now_utime));
  compute_tag(key_, channel, static_cast<const uint8_t*>(message), size, trailer,
              trailer + kTagOffset);
  std::memcpy(trailer + kMagicOffset, kMagic, sizeof kMagic);
}

Verifier::Verifier(const RigKey& key, VerifierConfig config) : key_(key), config_(config) {
  poly1305_context();
  HULLPOSE_THROW_UNLESS(config_.max_senders > 0, "auth: max_senders must be positive");
  HULLPOSE_THROW_UNLESS(config_.max_skew_us >= 0, "auth: max_skew must not be negative");
  windows_.reserve(config_.max_senders);
}

Verified Verifier::verify(std::string_view channel, const void* data, size_t size,
                          int64_t now_utime) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  if (size < kTrailerSize) return {Verdict::kMissing, 0};
  const size_t message_size = size - kTrailerSize;
  const uint8_t* t = bytes + message_size;
  if (std::memcmp(t + kMagicOffset, kMagic, sizeof kMagic) != 0) return {Verdict::kMissing, 0};
  if (get_u32(t) != key_.id()) return {Verdict::kWrongKey, 0};
  uint8_t tag[crypto_onetimeauth_BYTES];
  compute_tag(key_, channel, bytes, message_size, t, tag);
  if (crypto_verify_16(tag, t + kTagOffset) != 0) return {Verdict::kBadMac, 0};
  const auto sent = static_cast<int64_t>(get_u64(t + 28));
  // Written so that no subtraction overflows whatever sent_utime holds.
  if (config_.max_skew_us > 0 &&
      (sent > now_utime ? static_cast<uint64_t>(sent) - static_cast<uint64_t>(now_utime)
                        : static_cast<uint64_t>(now_utime) - static_cast<uint64_t>(sent)) >
          static_cast<uint64_t>(config_.max_skew_us))
    return {Verdict::kStale, 0};
  SenderId sender;
  std::memcpy(sender.data(), t + 4, sender.size());
  if (!accept(sender, get_u64(t + 20))) return {Verdict::kReplayed, 0};
  return {Verdict::kOk, message_size};
}

bool Verifier::accept(const SenderId& sender, uint64_t counter) {
  std::lock_guard lock(mutex_);
  ++tick_;
  auto it = std::find_if(windows_.begin(), windows_.end(),
                         [&](const Window& w) { return w.sender == sender; });
  if (it == windows_.end()) {
    if (windows_.size() < config_.max_senders) {
      it = windows_.emplace(windows_.end());  // capacity reserved: no allocation
    } else {
      it = std::min_element(windows_.begin(), windows_.end(), [](const Window& a, const Window& b) {
        return a.last_used < b.last_used;
      });
    }
    *it = Window{};
    it->sender = sender;
  }
  Window& w = *it;
  w.last_used = tick_;
  if (counter == 0) return false;  // signers start at 1
  if (counter > w.top) {
    const uint64_t shift = counter - w.top;
    if (shift >= kWindow) {
      w.seen.fill(0);
    } else {
      // seen <<= shift, over the words (word 0 holds bits 0..63).
      const size_t words = shift / 64, bits = shift % 64;
      for (size_t i = w.seen.size(); i-- > 0;) {
        uint64_t v = i >= words ? w.seen[i - words] << bits : 0;
        if (bits != 0 && i >= words + 1) v |= w.seen[i - words - 1] >> (64 - bits);
        w.seen[i] = v;
      }
    }
    w.top = counter;
    w.seen[0] |= 1;
    return true;
  }
  const uint64_t d = w.top - counter;
  if (d >= kWindow) return false;
  uint64_t& word = w.seen[d / 64];
  const uint64_t bit = uint64_t{1} << (d % 64);
  if (word & bit) return false;
  word |= bit;
  return true;
}

size_t strip_trailer(const void* data, size_t size) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  if (size >= kTrailerSize && std::memcmp(bytes + size - 4, kMagic, sizeof kMagic) == 0)
    return size - kTrailerSize;
  return size;
}

}  // namespace hullpose::auth
