// Fuzz target: the message authentication check (common/auth Verifier) on any bytes: never
// crashes, and accepts nothing that was not signed with the key (the MAC; a fuzzer that
// forged a tag would abort here; the seeds are signed with another key).
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "hullpose/auth/message_auth.hpp"

namespace {
hullpose::auth::RigKey fuzz_key() {
  std::array<uint8_t, hullpose::auth::RigKey::kSize> b{};
  for (size_t i = 0; i < b.size(); ++i) b[i] = static_cast<uint8_t>(i * 13 + 1);
  return hullpose::auth::RigKey(b);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static hullpose::auth::Verifier verifier(fuzz_key(), {.max_skew_us = 0});
  const auto r = verifier.verify("SILHOUETTE", data, size, 0);
  if (r.verdict == hullpose::auth::Verdict::kOk) std::abort();
  if (hullpose::auth::strip_trailer(data, size) > size) std::abort();
  return 0;
}

std::vector<std::vector<uint8_t>> hullpose_fuzz_seeds() {
  // Messages signed with ANOTHER key: well-formed trailers the fuzzer can mutate, but to be
  // accepted it would have to forge a tag under the verifier's key. (Seeds signed with the
  // verifier's key and then damaged would be repaired by the first mutation that undoes the
  // damage: that is not a forgery.)
  std::array<uint8_t, hullpose::auth::RigKey::kSize> other{};
  other.fill(0x77);
  hullpose::auth::Signer signer{hullpose::auth::RigKey(other)};
  std::vector<std::vector<uint8_t>> seeds;
  for (const size_t n : {0, 40, 300}) {
    std::vector<uint8_t> m(n + hullpose::auth::kTrailerSize, 0x42);
    signer.sign("SILHOUETTE", m.data(), n, 1'700'000'000'000'000, m.data() + n);
    seeds.push_back(m);
  }
  // The verifier's key id in a trailer too, so the fuzzer starts past the key id check.
  const uint32_t id = fuzz_key().id();
  auto forged = seeds.back();
  for (int i = 0; i < 4; ++i)
    forged[300 + static_cast<size_t>(i)] = static_cast<uint8_t>(id >> (24 - 8 * i));
  seeds.push_back(forged);
  return seeds;
}
