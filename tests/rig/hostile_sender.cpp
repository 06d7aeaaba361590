// A hostile peer on the silhouette channel, for the system tests: after every silhouette of
// camera --camera-id it hears, it publishes four bad copies on SILHOUETTE — random bytes, a
// truncated copy, a copy whose rig_id length is -1, a copy with one byte flipped — seeded, so a
// run is reproducible. Its own messages come back to it (multicast loopback) and are recognised
// and ignored, so it answers the camera only.
//   rig_hostile_sender --lcm-url URL --camera-id C [--duration-s S] [--seed N]
#include <csignal>
#include <cstdio>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <hullpose_msg/silhouette_t.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

class Hostile {
 public:
  Hostile(lcm::LCM& bus, int camera_id, uint32_t seed) : bus_(bus), camera_id_(camera_id), rng_(seed) {}

  void on_message(const lcm::ReceiveBuffer* rb, const std::string&) {
    const std::string_view bytes(static_cast<const char*>(rb->data), rb->data_size);
    for (size_t h : sent_)
      if (h == std::hash<std::string_view>{}(bytes)) return;  // our own
    if (msg_.decode(rb->data, 0, static_cast<int>(rb->data_size)) != static_cast<int>(rb->data_size) ||
        msg_.camera_id != camera_id_ || rb->data_size < 24)
      return;
    const auto* valid = static_cast<const uint8_t*>(rb->data);
    std::vector<uint8_t> b(rng_() % 300);
    for (auto& x : b) x = static_cast<uint8_t>(rng_());
    send(b);
    b.assign(valid, valid + rng_() % rb->data_size);
    send(b);
    b.assign(valid, valid + rb->data_size);
    for (size_t k = 0; k < 4; ++k) b[16 + k] = 0xFF;  // after the 8-byte fingerprint and utime: rig_id length -1
    send(b);
    b.assign(valid, valid + rb->data_size);
    b[rng_() % b.size()] ^= static_cast<uint8_t>(1 + rng_() % 255);
    send(b);
    ++answered_;
  }
  int64_t answered() const { return answered_; }
  int64_t sent() const { return sent_count_; }

 private:
  void send(const std::vector<uint8_t>& b) {
    sent_[next_++ % sent_.size()] = std::hash<std::string_view>{}({reinterpret_cast<const char*>(b.data()), b.size()});
    bus_.publish("SILHOUETTE", b.data(), static_cast<unsigned>(b.size()));
    ++sent_count_;
  }
  lcm::LCM& bus_;
  int camera_id_;
  std::mt19937 rng_;
  hullpose_msg::silhouette_t msg_;
  std::vector<size_t> sent_ = std::vector<size_t>(64, 0);
  size_t next_ = 0;
  int64_t answered_ = 0, sent_count_ = 0;
};
}  // namespace

int main(int argc, char** argv) {
  try {
    std::string url;
    int camera_id = -1;
    double duration_s = 3600;
    uint32_t seed = 1;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      HULLPOSE_THROW_UNLESS(i + 1 < argc, "option " << a << " needs a value");
      if (a == "--lcm-url") url = argv[++i];
      else if (a == "--camera-id") camera_id = std::stoi(argv[++i]);
      else if (a == "--duration-s") duration_s = std::stod(argv[++i]);
      else if (a == "--seed") seed = static_cast<uint32_t>(std::stoul(argv[++i]));
      else HULLPOSE_THROW("unknown option '" << a << "'");
    }
    HULLPOSE_THROW_UNLESS(camera_id >= 0, "--camera-id is required");
    lcm::LCM bus(url);
    HULLPOSE_THROW_UNLESS(bus.good(), "LCM '" << url << "' cannot be opened");
    Hostile hostile(bus, camera_id, seed);
    bus.subscribe("SILHOUETTE", &Hostile::on_message, &hostile);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const int64_t end = hullpose::monotonic_us() + static_cast<int64_t>(duration_s * 1e6);
    while (!g_stop && hullpose::monotonic_us() < end) bus.handleTimeout(100);
    std::fprintf(stderr, "rig_hostile_sender: answered %lld silhouettes of camera %d with %lld hostile messages\n",
                 static_cast<long long>(hostile.answered()), camera_id, static_cast<long long>(hostile.sent()));
    return 0;
  } catch (const hullpose::Error& e) {
    std::fprintf(stderr, "rig_hostile_sender: error: %s\n", e.what());
    return 2;
  }
}
