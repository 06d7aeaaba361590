// Rig key files: made private, read back, refused when others may read them or when malformed.
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "hullpose/auth/rig_key.hpp"
#include "hullpose/common/check.hpp"

namespace fs = std::filesystem;
using hullpose::auth::RigKey;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    char tmpl[] = "/tmp/hullpose-key.XXXXXX";
    path = ::mkdtemp(tmpl);
  }
  ~TempDir() { fs::remove_all(path); }
};

std::string write_file(const fs::path& p, const std::string& text, mode_t mode) {
  std::ofstream(p) << text;
  ::chmod(p.c_str(), mode);
  return p.string();
}

const std::string kHex = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

}  // namespace

TEST_CASE("a saved key is private and loads back to the same bytes and id") {
  TempDir d;
  const RigKey key = RigKey::generate();
  const std::string file = (d.path / "rig.key").string();
  key.save(file);
  struct stat st {};
  REQUIRE(::stat(file.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0600);
  const RigKey back = RigKey::load(file);
  CHECK(back.bytes() == key.bytes());
  CHECK(back.id() == key.id());
  CHECK(RigKey::generate().id() != key.id());  // 2^-32 chance of a false failure
  // Never overwrites an existing key.
  CHECK_THROWS_WITH(key.save(file), Catch::Contains("rig.key") && Catch::Contains("cannot create"));
}

TEST_CASE("a key file is read as 64 hex digits with an optional newline") {
  TempDir d;
  const RigKey a = RigKey::load(write_file(d.path / "a", kHex + "\n", 0600));
  const RigKey b = RigKey::load(write_file(d.path / "b", kHex, 0400));
  CHECK(a.bytes() == b.bytes());
  CHECK(a.bytes()[31] == 0x1f);
}

TEST_CASE("a key file others may read or write is refused, naming the file and the fix") {
  TempDir d;
  for (const mode_t mode : {0644, 0640, 0604, 0620, 0602, 0660}) {
    const std::string file = write_file(d.path / ("k" + std::to_string(mode)), kHex + "\n", mode);
    CHECK_THROWS_WITH(RigKey::load(file), Catch::Contains(file) && Catch::Contains("chmod 600"));
  }
}

TEST_CASE("malformed or missing key files are errors naming the file") {
  TempDir d;
  const char* bad[] = {"",
                       "\n",
                       "00",
                       "zz0102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f",
                       "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f00",
                       "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f\n\n",
                       " 000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f"};
  int i = 0;
  for (const char* text : bad) {
    const std::string file = write_file(d.path / ("bad" + std::to_string(i++)), text, 0600);
    CHECK_THROWS_WITH(RigKey::load(file),
                      Catch::Contains(file) && Catch::Contains("64 hex digits"));
  }
  CHECK_THROWS_WITH(RigKey::load((d.path / "none").string()),
                    Catch::Contains("none") && Catch::Contains("cannot open"));
  ::chmod(d.path.c_str(), 0700);
  CHECK_THROWS_WITH(RigKey::load(d.path.string()), Catch::Contains("not a regular file"));
}
