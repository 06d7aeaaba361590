#pragma once
// The tag of docs/messages.md's construction computed with libsodium alone (XChaCha20 one-time
// key, crypto_onetimeauth): the reference that common/auth's tag, computed with OpenSSL's
// Poly1305, is tested against (test_message_auth.cpp), and the "before" of bench_auth.
#include <sodium.h>

#include <array>
#include <cstdint>
#include <string_view>

#include "hullpose/auth/rig_key.hpp"

namespace hullpose::auth::testing {

// `trailer` is the message's trailer; its first 36 bytes (key id, sender, counter, sent_utime)
// are signed, bytes 4..28 are the nonce.
inline std::array<uint8_t, crypto_onetimeauth_BYTES> reference_tag(const RigKey& key,
                                                                   std::string_view channel,
                                                                   const uint8_t* message,
                                                                   size_t size,
                                                                   const uint8_t* trailer) {
  uint8_t one_time[crypto_onetimeauth_KEYBYTES];
  crypto_stream_xchacha20(one_time, sizeof one_time, trailer + 4, key.bytes().data());
  crypto_onetimeauth_state s;
  crypto_onetimeauth_init(&s, one_time);
  const auto n = static_cast<uint32_t>(channel.size());
  const uint8_t len[4] = {static_cast<uint8_t>(n >> 24), static_cast<uint8_t>(n >> 16),
                          static_cast<uint8_t>(n >> 8), static_cast<uint8_t>(n)};
  crypto_onetimeauth_update(&s, len, sizeof len);
  crypto_onetimeauth_update(&s, reinterpret_cast<const uint8_t*>(channel.data()), channel.size());
  crypto_onetimeauth_update(&s, message, size);
  crypto_onetimeauth_update(&s, trailer, 36);
  std::array<uint8_t, crypto_onetimeauth_BYTES> tag{};
  crypto_onetimeauth_final(&s, tag.data());
  return tag;
}

}  // namespace hullpose::auth::testing
