// Message authentication: what a receiver accepts and, for everything else, the reason it drops.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "hullpose/auth/message_auth.hpp"
#include "reference_tag.hpp"

using namespace hullpose::auth;

namespace {

constexpr int64_t kNow = 1'700'000'000'000'000;

RigKey key_from(uint8_t seed) {
  std::array<uint8_t, RigKey::kSize> b{};
  for (size_t i = 0; i < b.size(); ++i) b[i] = static_cast<uint8_t>(seed + 7 * i);
  return RigKey(b);
}

SenderId sender_from(uint8_t seed) {
  SenderId s{};
  s.fill(seed);
  return s;
}

std::vector<uint8_t> message(size_t n, uint8_t seed = 1) {
  std::vector<uint8_t> m(n);
  for (size_t i = 0; i < n; ++i) m[i] = static_cast<uint8_t>(seed + i * 31);
  return m;
}

std::vector<uint8_t> signed_copy(Signer& signer, const std::string& channel, std::vector<uint8_t> m,
                                 int64_t now = kNow) {
  const size_t n = m.size();
  m.resize(n + kTrailerSize);
  signer.sign(channel, m.data(), n, now, m.data() + n);
  return m;
}

Verdict check(Verifier& v, const std::string& channel, const std::vector<uint8_t>& m,
              int64_t now = kNow) {
  return v.verify(channel, m.data(), m.size(), now).verdict;
}

}  // namespace

TEST_CASE("a signed message verifies and the trailer is stripped") {
  const RigKey key = key_from(1);
  Signer signer(key);
  Verifier verifier(key);
  for (const size_t n : {0, 1, 55, 56, 3000, 70000}) {
    const auto m = message(n);
    const auto s = signed_copy(signer, "SILHOUETTE", m);
    REQUIRE(s.size() == n + kTrailerSize);
    const Verified r = verifier.verify("SILHOUETTE", s.data(), s.size(), kNow);
    CHECK(r.verdict == Verdict::kOk);
    CHECK(r.message_size == n);
    CHECK(strip_trailer(s.data(), s.size()) == n);
    CHECK(std::equal(m.begin(), m.end(), s.begin()));  // memcmp would take null for n = 0
  }
}

// The tag is computed with OpenSSL's Poly1305 (faster than libsodium's); it must be the bytes of
// the construction docs/messages.md states, computed with libsodium alone, on every thread.
TEST_CASE("the tag is the documented XChaCha20 + Poly1305 construction, on any thread") {
  REQUIRE(sodium_init() >= 0);
  const RigKey key = key_from(9);
  Signer signer(key, sender_from(4));
  auto matches = [&](const std::string& channel, const std::vector<uint8_t>& s, size_t n) {
    const auto expected = testing::reference_tag(key, channel, s.data(), n, s.data() + n);
    return std::equal(expected.begin(), expected.end(),
                      s.begin() + static_cast<std::ptrdiff_t>(n) + 36);
  };
  for (const size_t n : {0, 1, 15, 16, 17, 3000, 16000, 70000}) {
    const auto m = message(n, static_cast<uint8_t>(n));
    const auto s = signed_copy(signer, "SILHOUETTE", m);
    CHECK(matches("SILHOUETTE", s, n));
    std::vector<uint8_t> other;
    std::thread([&] { other = signed_copy(signer, "SKELETON", m); }).join();
    CHECK(matches("SKELETON", other, n));
  }
}

TEST_CASE("any changed bit of message, channel or trailer fails the MAC") {
  const RigKey key = key_from(2);
  Signer signer(key, sender_from(9));
  const auto s = signed_copy(signer, "TRIGGER", message(100));
  for (size_t i = 0; i < s.size() - 4; ++i) {  // the magic is checked before the MAC
    for (const uint8_t bit : {0x01, 0x80}) {
      Verifier v(key);
      auto t = s;
      t[i] ^= bit;
      const Verdict got = check(v, "TRIGGER", t);
      INFO("byte " << i);
      if (i >= 100 && i < 104)
        CHECK(got == Verdict::kWrongKey);  // the key id
      else
        CHECK(got == Verdict::kBadMac);
    }
  }
  Verifier v(key);
  CHECK(check(v, "TRIGGEr", s) == Verdict::kBadMac);
  CHECK(check(v, "SILHOUETTE", s) == Verdict::kBadMac);  // a message moved to another channel
  CHECK(check(v, "TRIGGER", s) == Verdict::kOk);
}

TEST_CASE("messages without a trailer, of another rig, or forged are told apart") {
  const RigKey ours = key_from(3), theirs = key_from(4);
  REQUIRE(ours.id() != theirs.id());
  Verifier v(ours);
  CHECK(check(v, "SKELETON", message(300)) == Verdict::kMissing);
  CHECK(check(v, "SKELETON", message(3)) == Verdict::kMissing);
  CHECK(check(v, "SKELETON", {}) == Verdict::kMissing);
  Signer other_rig(theirs);
  CHECK(check(v, "SKELETON", signed_copy(other_rig, "SKELETON", message(300))) ==
        Verdict::kWrongKey);
  // A forger who copies our key id and a plausible trailer but has no key.
  Signer mine(ours);
  auto forged = signed_copy(mine, "SKELETON", message(300));
  forged[10] ^= 1;  // changed content, same trailer
  CHECK(check(v, "SKELETON", forged) == Verdict::kBadMac);
  std::mt19937 rng(7);
  for (int i = 0; i < 2000; ++i) {
    auto t = forged;
    for (size_t b = 300 + 4; b < 300 + 52; ++b) t[b] = static_cast<uint8_t>(rng());
    REQUIRE(check(v, "SKELETON", t) != Verdict::kOk);
  }
}

TEST_CASE("a replayed or duplicated message is dropped; reordering inside the window is not") {
  const RigKey key = key_from(5);
  Signer signer(key, sender_from(1));
  Verifier v(key);
  std::vector<std::vector<uint8_t>> sent;
  for (int i = 0; i < 600; ++i)
    sent.push_back(
        signed_copy(signer, i % 2 ? "STATUS" : "SILHOUETTE", message(40, static_cast<uint8_t>(i))));
  const auto channel = [](int i) { return i % 2 ? "STATUS" : "SILHOUETTE"; };
  // In order, each once.
  for (int i = 0; i < 10; ++i) CHECK(check(v, channel(i), sent[i]) == Verdict::kOk);
  for (int i = 0; i < 10; ++i) CHECK(check(v, channel(i), sent[i]) == Verdict::kReplayed);
  // Pairs swapped, then every one again.
  for (int i = 10; i < 300; i += 2) {
    CHECK(check(v, channel(i + 1), sent[i + 1]) == Verdict::kOk);
    CHECK(check(v, channel(i), sent[i]) == Verdict::kOk);
  }
  for (int i = 10; i < 300; ++i) CHECK(check(v, channel(i), sent[i]) == Verdict::kReplayed);
  // A gap (lost messages), then a late one inside the window and one behind it.
  CHECK(check(v, channel(599), sent[599]) == Verdict::kOk);
  CHECK(check(v, channel(599 - 255), sent[599 - 255]) == Verdict::kOk);
  CHECK(check(v, channel(599 - 256), sent[599 - 256]) == Verdict::kReplayed);
  CHECK(check(v, channel(320), sent[320]) ==
        Verdict::kReplayed);  // never accepted, but behind the window
  CHECK(check(v, channel(350), sent[350]) == Verdict::kOk);  // never accepted, inside it
}

TEST_CASE("every shift of the replay window keeps exactly the counters accepted") {
  const RigKey key = key_from(6);
  Signer signer(key, sender_from(2));
  Verifier v(key);
  std::mt19937 rng(3);
  std::vector<std::vector<uint8_t>> sent;
  for (int i = 0; i < 3000; ++i)
    sent.push_back(signed_copy(signer, "X", message(8, static_cast<uint8_t>(i))));
  std::vector<bool> accepted(sent.size(), false);
  size_t top = 0;
  for (int step = 0; step < 20000; ++step) {
    // Mostly forward by 1..300, sometimes back: compare with a model of the window.
    size_t i = std::min(sent.size() - 1, top + rng() % 300);
    if (rng() % 2) i = top >= 300 ? top - rng() % 300 : rng() % (top + 1);
    const bool fresh = !accepted[i] && (i >= top || top - i < Verifier::kWindow);
    INFO("step " << step << " counter index " << i << " top " << top);
    REQUIRE((check(v, "X", sent[i]) == Verdict::kOk) == fresh);
    if (fresh) {
      accepted[i] = true;
      top = std::max(top, i);
    }
  }
}

TEST_CASE("a message far from the receiver's clock is stale unless the time check is off") {
  const RigKey key = key_from(7);
  Signer signer(key);
  Verifier strict(key, {.max_skew_us = 1'000'000});
  Verifier off(key, {.max_skew_us = 0});
  const auto m = signed_copy(signer, "TRIGGER", message(50), kNow);
  CHECK(check(strict, "TRIGGER", m, kNow + 1'000'001) == Verdict::kStale);
  CHECK(check(strict, "TRIGGER", m, kNow - 1'000'001) == Verdict::kStale);
  CHECK(check(strict, "TRIGGER", m, kNow + 999'999) == Verdict::kOk);
  CHECK(check(off, "TRIGGER", m, 0) == Verdict::kOk);
  // Extreme sent times do not overflow the comparison.
  for (const int64_t t : {INT64_MIN, INT64_MAX, int64_t{0}, int64_t{-1}})
    CHECK(check(strict, "TRIGGER", signed_copy(signer, "TRIGGER", message(5), t), kNow) ==
          Verdict::kStale);
}

TEST_CASE("the sender table is bounded: the least recently heard sender is forgotten") {
  const RigKey key = key_from(8);
  Verifier v(key, {.max_skew_us = 0, .max_senders = 2});
  Signer a(key, sender_from(1)), b(key, sender_from(2)), c(key, sender_from(3));
  const auto a1 = signed_copy(a, "S", message(4)), b1 = signed_copy(b, "S", message(4)),
             c1 = signed_copy(c, "S", message(4));
  CHECK(check(v, "S", a1) == Verdict::kOk);
  CHECK(check(v, "S", b1) == Verdict::kOk);
  CHECK(check(v, "S", a1) == Verdict::kReplayed);  // a heard again: b is now the oldest
  CHECK(check(v, "S", c1) == Verdict::kOk);        // b forgotten
  CHECK(check(v, "S", a1) == Verdict::kReplayed);
  CHECK(check(v, "S", c1) == Verdict::kReplayed);
  // Why the time check exists: a forgotten sender's old message is accepted again.
  CHECK(check(v, "S", b1) == Verdict::kOk);
}

TEST_CASE("strip_trailer leaves messages without a trailer whole") {
  const auto m = message(200);
  CHECK(strip_trailer(m.data(), m.size()) == 200);
  CHECK(strip_trailer(m.data(), 10) == 10);
  CHECK(counter_name(Verdict::kReplayed) == "auth_replayed");
  CHECK(counter_name(Verdict::kWrongKey) == "auth_wrong_key");
}
