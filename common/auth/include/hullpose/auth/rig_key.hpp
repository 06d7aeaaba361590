#pragma once
// The secret of one rig: 32 random bytes shared by every process of the rig, kept in a key file
// (one line of 64 hex digits) that only its owner may read. Every message on the rig's LCM
// channels carries a MAC made with it (message_auth.hpp); a host without the file can read the
// rig's messages but cannot publish any that the rig accepts.
#include <array>
#include <cstdint>
#include <string>

namespace hullpose::auth {

class RigKey {
 public:
  static constexpr size_t kSize = 32;

  // Reads a key file. Throws hullpose::Error naming the file when it is missing, not a regular
  // file, readable or writable by group or others (like ssh's private keys), or not exactly 64
  // hex digits (optionally followed by a newline).
  static RigKey load(const std::string& path);
  // A fresh random key (libsodium's CSPRNG).
  static RigKey generate();
  // From raw bytes (tests, benchmarks).
  explicit RigKey(const std::array<uint8_t, kSize>& bytes);

  // Writes the key to a new file with mode 0600; refuses to overwrite an existing file.
  void save(const std::string& path) const;

  const std::array<uint8_t, kSize>& bytes() const { return bytes_; }
  // A public fingerprint of the key (BLAKE2b of it): lets a receiver tell a message of another
  // rig (different key) from a forgery (same fingerprint, wrong MAC).
  uint32_t id() const { return id_; }

  RigKey(const RigKey&) = default;
  RigKey& operator=(const RigKey&) = default;
  ~RigKey();

 private:
  std::array<uint8_t, kSize> bytes_{};
  uint32_t id_ = 0;
};

}  // namespace hullpose::auth
