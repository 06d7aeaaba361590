// A foreign host on the rig's LAN for the attacker test (tests/system/rig_attacker_test.sh): it
// knows the message formats and the rig id but not the rig's key. For every genuine TRIGGER,
// SILHOUETTE and SKELETON it hears it publishes FACTOR forged ones on the same channel (so 10x
// the rig's rate with the default), cycling through what such a host can make:
//   0 a plausible message (right rig id, the next or current sequence, a view of the wrong
//     instant, a trigger of another epoch, a skeleton far off) with no trailer
//   1 the same with a trailer copied from the genuine message (key id, sender, counter) and a
//     random tag
//   2 the same with a trailer of another key id
//   3 the genuine message verbatim again (a replay)
//   4 the genuine message with one byte of its body changed and its own trailer (tampering)
// Seeded, so a run is reproducible; its own messages come back to it and are ignored.
//   rig_attacker --lcm-url URL [--factor N=10] [--duration-s S] [--seed N]
#include <cstdio>
#include <cstring>
#include <functional>
#include <hullpose_msg/silhouette_t.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "hullpose/auth/message_auth.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/silhouette_codec.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "seq_pattern.hpp"

namespace {
using hullpose::auth::kTrailerSize;

class Attacker {
 public:
  Attacker(lcm::LCM& bus, int factor, uint32_t seed) : bus_(bus), factor_(factor), rng_(seed) {}

  void on_message(const lcm::ReceiveBuffer* rb, const std::string& channel) {
    const auto* bytes = static_cast<const uint8_t*>(rb->data);
    const size_t size = rb->data_size;
    const size_t h = std::hash<std::string_view>{}({static_cast<const char*>(rb->data), size});
    for (size_t s : sent_)
      if (s == h) return;  // our own, back from the multicast loop
    ++heard_;
    // The genuine message without its trailer, and the trailer (if it has one).
    const size_t body = hullpose::auth::strip_trailer(bytes, size);
    genuine_.assign(bytes, bytes + size);
    for (int i = 0; i < factor_; ++i) {
      const int kind = static_cast<int>(next_kind_++ % 5);
      if (kind == 3) {
        send(channel, genuine_);
      } else if (kind == 4) {
        out_ = genuine_;
        if (body > 20) out_[20 + rng_() % (body - 20)] ^= static_cast<uint8_t>(1 + rng_() % 255);
        send(channel, out_);
      } else if (forge(channel, bytes, body)) {
        if (kind >= 1) {
          const size_t n = out_.size();
          out_.resize(n + kTrailerSize);
          if (body < size)
            std::memcpy(out_.data() + n, bytes + body, kTrailerSize);  // a real trailer's fields
          for (size_t k = 36; k < 52; ++k)
            out_[n + k] = static_cast<uint8_t>(rng_());  // a tag made up
          std::memcpy(out_.data() + n + 52, "HPA1", 4);
          if (kind == 2)
            for (size_t k = 0; k < 4; ++k) out_[n + k] ^= 0x5a;  // another key id
        }
        send(channel, out_);
      }
    }
  }
  long long heard() const { return heard_; }
  long long sent() const { return sent_count_; }

 private:
  // A plausible message of the channel's type from the genuine one's fields, in out_.
  bool forge(const std::string& channel, const uint8_t* bytes, size_t body) {
    const int n = static_cast<int>(body);
    if (channel == "SILHOUETTE" && sil_.decode(bytes, 0, n) == n) {
      // The same camera and instant, but the view of another instant: fused, it would mix.
      cv::Mat mask(sil_.height, sil_.width, CV_8UC1);
      hullpose::testing::draw_seq_mask(
          mask, sil_.trigger_seq + 1 + static_cast<int64_t>(rng_() % 50), sil_.camera_id);
      encoder_.encode(mask, payload_);
      sil_.roi_x = sil_.roi_y = 0;
      sil_.roi_width = sil_.width;
      sil_.roi_height = sil_.height;
      sil_.payload.assign(payload_.begin(), payload_.end());
      sil_.payload_size = static_cast<int32_t>(payload_.size());
      return encode(sil_);
    }
    if (channel == "TRIGGER" && trig_.decode(bytes, 0, n) == n) {
      trig_.seq += 1 + static_cast<int64_t>(rng_() % 3);
      trig_.utime += trig_.period_us;
      trig_.epoch ^= static_cast<int64_t>(rng_() % 2) << 7;
      return encode(trig_);
    }
    if (channel == "SKELETON" && skel_.decode(bytes, 0, n) == n) {
      for (auto& p : skel_.position) p[2] += 500.f;  // the person half a metre up
      skel_.valid = true;
      return encode(skel_);
    }
    return false;
  }
  template <typename Msg>
  bool encode(const Msg& m) {
    out_.resize(static_cast<size_t>(m.getEncodedSize()));
    return m.encode(out_.data(), 0, static_cast<int>(out_.size())) > 0;
  }
  void send(const std::string& channel, const std::vector<uint8_t>& b) {
    sent_[next_++ % sent_.size()] =
        std::hash<std::string_view>{}({reinterpret_cast<const char*>(b.data()), b.size()});
    bus_.publish(channel, b.data(), static_cast<unsigned>(b.size()));
    ++sent_count_;
  }

  lcm::LCM& bus_;
  int factor_;
  std::mt19937 rng_;
  uint64_t next_kind_ = 0;
  hullpose_msg::silhouette_t sil_;
  hullpose_msg::trigger_t trig_;
  hullpose_msg::skeleton_t skel_;
  hullpose::SilhouetteEncoder encoder_;
  std::vector<uint8_t> payload_, out_, genuine_;
  std::vector<size_t> sent_ = std::vector<size_t>(1024, 0);
  size_t next_ = 0;
  long long heard_ = 0, sent_count_ = 0;
};
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("rig_attacker", argc, argv, [](int c, const char* const* v) {
    std::string url;
    long long factor = 10;
    double duration_s = 3600;
    uint64_t seed = 1;
    hullpose::cli::CommandLine cl(
        "usage: rig_attacker --lcm-url URL [--factor N=10] [--duration-s S] [--seed N]\n");
    cl.option("--lcm-url", url)
        .option("--factor", factor)
        .option("--duration-s", duration_s)
        .option("--seed", seed);
    if (!cl.parse(c, v)) return 0;
    HULLPOSE_THROW_UNLESS(factor >= 1 && factor <= 1000,
                          "--factor must be 1..1000, got " << factor);
    lcm::LCM bus(url);
    HULLPOSE_THROW_UNLESS(bus.good(), "LCM '" << url << "' cannot be opened");
    Attacker attacker(bus, static_cast<int>(factor), static_cast<uint32_t>(seed));
    for (const char* channel : {"TRIGGER", "SILHOUETTE", "SKELETON"})
      bus.subscribe(channel, &Attacker::on_message, &attacker)->setQueueCapacity(1000);
    hullpose::catch_stop_signals();
    const int64_t end = hullpose::monotonic_us() + static_cast<int64_t>(duration_s * 1e6);
    while (!hullpose::stop_requested() && hullpose::monotonic_us() < end) bus.handleTimeout(100);
    std::fprintf(stderr, "rig_attacker: heard %lld genuine messages, published %lld forged ones\n",
                 attacker.heard(), attacker.sent());
    return 0;
  });
}
