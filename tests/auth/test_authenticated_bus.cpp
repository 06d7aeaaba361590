// The authenticating bus over LCM's in-process provider: what reaches the handlers of a rig with
// a key, what is dropped and counted, and that an open process reads an authenticated rig.
#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>

#include "hullpose/auth/authenticated_bus.hpp"

using namespace hullpose;

namespace {

constexpr int64_t kNow = 1'700'000'000'000'000;

auth::RigKey key_from(uint8_t seed) {
  std::array<uint8_t, auth::RigKey::kSize> b{};
  b.fill(seed);
  return auth::RigKey(b);
}

// A non-owning view of one memq bus, so that several wrappers share it like processes share a LAN.
class Shared final : public bus::Bus {
 public:
  explicit Shared(bus::Bus& b) : b_(b) {}
  bool publish(const std::string& c, std::span<const uint8_t> bytes) override {
    return b_.publish(c, bytes);
  }
  bus::Subscription subscribe(const std::string& c, bus::Handler h, int q) override {
    return b_.subscribe(c, std::move(h), q);
  }
  bool handle(int t) override { return b_.handle(t); }
  int fd() const override { return b_.fd(); }
  const std::string& url() const override { return b_.url(); }

 private:
  bus::Bus& b_;
};

std::unique_ptr<auth::AuthenticatedBus> wrap(bus::Bus& lan, std::optional<auth::RigKey> key) {
  return std::make_unique<auth::AuthenticatedBus>(std::make_unique<Shared>(lan), std::move(key),
                                                  auth::VerifierConfig{}, [] { return kNow; });
}

int64_t drops(const bus::Bus& b, const std::string& reason) {
  for (const auto& [name, value] : b.drops())
    if (name == reason) return value;
  return 0;
}

}  // namespace

TEST_CASE("a rig's processes hear each other; forged, foreign and replayed messages are counted") {
  auto lan = bus::open_lcm_bus("memq://");
  auto sender = wrap(*lan, key_from(1)), receiver = wrap(*lan, key_from(1)),
       other_rig = wrap(*lan, key_from(2));
  std::vector<std::string> got;
  auto sub = receiver->subscribe("TRIGGER", [&](std::span<const uint8_t> b, const std::string&) {
    got.emplace_back(reinterpret_cast<const char*>(b.data()), b.size());
  });
  // The raw traffic too, to replay it as an attacker would.
  std::vector<std::vector<uint8_t>> raw;
  auto tap = lan->subscribe("TRIGGER", [&](std::span<const uint8_t> b, const std::string&) {
    raw.emplace_back(b.begin(), b.end());
  });
  const std::string a = "first message", b = "second";
  REQUIRE(sender->publish("TRIGGER", {reinterpret_cast<const uint8_t*>(a.data()), a.size()}));
  REQUIRE(sender->publish("TRIGGER", {reinterpret_cast<const uint8_t*>(b.data()), b.size()}));
  REQUIRE(other_rig->publish("TRIGGER", {reinterpret_cast<const uint8_t*>(a.data()), a.size()}));
  REQUIRE(lan->publish("TRIGGER",
                       {reinterpret_cast<const uint8_t*>(a.data()), a.size()}));  // unauthenticated
  while (lan->handle(0)) {
  }
  REQUIRE(raw.size() == 4);
  CHECK(raw[0].size() == a.size() + auth::kTrailerSize);
  lan->publish("TRIGGER", raw[0]);  // replayed
  auto tampered = raw[1];
  tampered[0] ^= 1;
  lan->publish("TRIGGER", tampered);
  while (lan->handle(0)) {
  }
  CHECK(got == std::vector<std::string>{a, b});  // the handlers never see a trailer
  CHECK(drops(*receiver, "auth_wrong_key") == 1);
  CHECK(drops(*receiver, "auth_missing") == 1);
  CHECK(drops(*receiver, "auth_replayed") == 1);
  CHECK(drops(*receiver, "auth_bad_mac") == 1);
  CHECK(drops(*receiver, "auth_stale") == 0);
  CHECK(receiver->authenticated());
}

TEST_CASE("an open process (no key) reads signed and unsigned messages alike and signs nothing") {
  auto lan = bus::open_lcm_bus("memq://");
  auto signed_sender = wrap(*lan, key_from(1)), open = wrap(*lan, std::nullopt);
  std::vector<std::string> got;
  auto sub = open->subscribe("S", [&](std::span<const uint8_t> b, const std::string&) {
    got.emplace_back(reinterpret_cast<const char*>(b.data()), b.size());
  });
  size_t raw_size = 0;
  auto tap = lan->subscribe(
      "S", [&](std::span<const uint8_t> b, const std::string&) { raw_size = b.size(); });
  const std::string m = "hello";
  signed_sender->publish("S", {reinterpret_cast<const uint8_t*>(m.data()), m.size()});
  while (lan->handle(0)) {
  }
  open->publish("S", {reinterpret_cast<const uint8_t*>(m.data()), m.size()});
  while (lan->handle(0)) {
  }
  CHECK(got == std::vector<std::string>{m, m});
  CHECK(raw_size == m.size());  // the open process's own message carries no trailer
  CHECK_FALSE(open->authenticated());
  CHECK(drops(*open, "auth_missing") == 0);
}
