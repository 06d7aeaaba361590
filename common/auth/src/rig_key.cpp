#include "hullpose/auth/rig_key.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "hullpose/common/check.hpp"

namespace hullpose::auth {
namespace {

void init_sodium() {
  HULLPOSE_THROW_UNLESS(sodium_init() >= 0, "libsodium cannot be initialised");
}

// Closes a file descriptor on every path out.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

RigKey::RigKey(const std::array<uint8_t, kSize>& bytes) : bytes_(bytes) {
  init_sodium();
  static constexpr char kContext[] = "hullpose rig key id";
  crypto_generichash_state s;
  crypto_generichash_init(&s, nullptr, 0, 4);
  crypto_generichash_update(&s, reinterpret_cast<const uint8_t*>(kContext), sizeof kContext);
  crypto_generichash_update(&s, bytes_.data(), bytes_.size());
  uint8_t id[4];
  crypto_generichash_final(&s, id, sizeof id);
  id_ = (uint32_t{id[0]} << 24) | (uint32_t{id[1]} << 16) | (uint32_t{id[2]} << 8) | id[3];
}

RigKey::~RigKey() {
  sodium_memzero(bytes_.data(), bytes_.size());
}

RigKey RigKey::generate() {
  init_sodium();
  std::array<uint8_t, kSize> b;
  randombytes_buf(b.data(), b.size());
  RigKey key(b);
  sodium_memzero(b.data(), b.size());
  return key;
}

RigKey RigKey::load(const std::string& path) {
  const Fd f{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
  HULLPOSE_THROW_UNLESS(f.fd >= 0,
                        "rig key '" << path << "': cannot open: " << std::strerror(errno));
  struct stat st {};
  HULLPOSE_THROW_UNLESS(::fstat(f.fd, &st) == 0,
                        "rig key '" << path << "': cannot stat: " << std::strerror(errno));
  HULLPOSE_THROW_UNLESS(S_ISREG(st.st_mode), "rig key '" << path << "': not a regular file");
  const unsigned mode = st.st_mode & 07777;
  HULLPOSE_THROW_UNLESS((mode & 077) == 0,
                        "rig key '" << path << "': permissions 0" << std::oct << mode << std::dec
                                    << " let group or others access it; run chmod 600 '" << path
                                    << "'");
  // 64 hex digits, an optional newline, nothing else.
  char text[2 * kSize + 3] = {};
  ssize_t got = 0;
  while (got < static_cast<ssize_t>(sizeof text)) {
    const ssize_t n = ::read(f.fd, text + got, sizeof text - static_cast<size_t>(got));
    if (n < 0 && errno == EINTR) continue;
    HULLPOSE_THROW_UNLESS(n >= 0,
                          "rig key '" << path << "': cannot read: " << std::strerror(errno));
    if (n == 0) break;
    got += n;
  }
  size_t len = static_cast<size_t>(got);
  if (len > 0 && text[len - 1] == '\n') --len;
  std::array<uint8_t, kSize> b{};
  size_t decoded = 0;
  const char* end = nullptr;
  const bool ok = len == 2 * kSize &&
                  sodium_hex2bin(b.data(), b.size(), text, len, nullptr, &decoded, &end) == 0 &&
                  decoded == kSize && end == text + len;
  sodium_memzero(text, sizeof text);
  HULLPOSE_THROW_UNLESS(ok, "rig key '" << path << "': must hold exactly " << 2 * kSize
                                        << " hex digits (make one with hullpose-rig-key)");
  RigKey key(b);
  sodium_memzero(b.data(), b.size());
  return key;
}

void RigKey::save(const std::string& path) const {
  const Fd f{::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600)};
  HULLPOSE_THROW_UNLESS(f.fd >= 0,
                        "rig key '" << path << "': cannot create: " << std::strerror(errno));
  // The umask may have cleared bits but never adds any; make the mode exact anyway.
  HULLPOSE_THROW_UNLESS(::fchmod(f.fd, 0600) == 0,
                        "rig key '" << path << "': cannot chmod: " << std::strerror(errno));
  char text[2 * kSize + 2];
  sodium_bin2hex(text, sizeof text, bytes_.data(), bytes_.size());
  text[2 * kSize] = '\n';
  const bool ok = ::write(f.fd, text, 2 * kSize + 1) == static_cast<ssize_t>(2 * kSize + 1);
  sodium_memzero(text, sizeof text);
  HULLPOSE_THROW_UNLESS(ok && ::fsync(f.fd) == 0,
                        "rig key '" << path << "': cannot write: " << std::strerror(errno));
}

}  // namespace hullpose::auth
