// A hostile peer on the silhouette channel, for the system tests: after every silhouette of
// camera --camera-id it hears, it publishes four bad copies on SILHOUETTE — random bytes, a
// truncated copy, a copy whose rig_id length is -1, a copy with one byte flipped — seeded, so a
// run is reproducible. Its own messages come back to it (multicast loopback) and are recognised
// and ignored, so it answers the camera only.
//   rig_hostile_sender --lcm-url URL --camera-id C [--duration-s S] [--seed N]
#include <cstdio>
#include <functional>
#include <hullpose_msg/silhouette_t.hpp>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/msg/wire.hpp"

namespace {
class Hostile {
 public:
  Hostile(hullpose::bus::Bus& bus, int camera_id, uint32_t seed)
      : bus_(bus), camera_id_(camera_id), rng_(seed) {}

  void on_message(std::span<const uint8_t> message) {
    const std::string_view bytes(reinterpret_cast<const char*>(message.data()), message.size());
    for (size_t h : sent_)
      if (h == std::hash<std::string_view>{}(bytes)) return;  // our own
    if (!hullpose::wire::decode(message, msg_) || msg_.camera_id != camera_id_ ||
        message.size() < 24)
      return;
    const uint8_t* valid = message.data();
    const size_t size = message.size();
    std::vector<uint8_t> b(rng_() % 300);
    for (auto& x : b) x = static_cast<uint8_t>(rng_());
    send(b);
    b.assign(valid, valid + rng_() % size);
    send(b);
    b.assign(valid, valid + size);
    for (size_t k = 0; k < 4; ++k)
      b[16 + k] = 0xFF;  // after the 8-byte fingerprint and utime: rig_id length -1
    send(b);
    b.assign(valid, valid + size);
    b[rng_() % b.size()] ^= static_cast<uint8_t>(1 + rng_() % 255);
    send(b);
    ++answered_;
  }
  int64_t answered() const { return answered_; }
  int64_t sent() const { return sent_count_; }

 private:
  void send(const std::vector<uint8_t>& b) {
    sent_[next_++ % sent_.size()] =
        std::hash<std::string_view>{}({reinterpret_cast<const char*>(b.data()), b.size()});
    bus_.publish("SILHOUETTE", b);
    ++sent_count_;
  }
  hullpose::bus::Bus& bus_;
  int camera_id_;
  std::mt19937 rng_;
  hullpose_msg::silhouette_t msg_;
  std::vector<size_t> sent_ = std::vector<size_t>(64, 0);
  size_t next_ = 0;
  int64_t answered_ = 0, sent_count_ = 0;
};
int run(int argc, const char* const* argv) {
  std::string url;
  int camera_id = -1;
  double duration_s = 3600;
  long long seed = 1;
  hullpose::cli::CommandLine cl(
      "usage: rig_hostile_sender --lcm-url URL --camera-id C [--duration-s S] [--seed N]\n");
  cl.option("--lcm-url", url)
      .option("--camera-id", camera_id)
      .option("--duration-s", duration_s)
      .option("--seed", seed);
  if (!cl.parse(argc, argv)) return 0;
  HULLPOSE_THROW_UNLESS(camera_id >= 0, "--camera-id is required");
  const auto bus = hullpose::bus::open_bus(url);
  Hostile hostile(*bus, camera_id, static_cast<uint32_t>(seed));
  const auto sub =
      bus->subscribe("SILHOUETTE", [&hostile](std::span<const uint8_t> bytes, const std::string&) {
        hostile.on_message(bytes);
      });
  hullpose::catch_stop_signals();
  const int64_t end = hullpose::monotonic_us() + static_cast<int64_t>(duration_s * 1e6);
  while (!hullpose::stop_requested() && hullpose::monotonic_us() < end) bus->handle(100);
  std::fprintf(
      stderr,
      "rig_hostile_sender: answered %lld silhouettes of camera %d with %lld hostile messages\n",
      static_cast<long long>(hostile.answered()), camera_id,
      static_cast<long long>(hostile.sent()));
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("rig_hostile_sender", argc, argv, run);
}
