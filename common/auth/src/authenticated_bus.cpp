#include "hullpose/auth/authenticated_bus.hpp"

#include <cstring>
#include <vector>

#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::auth {
namespace {
HULLPOSE_LOG_CATEGORY(Auth, "auth")
}  // namespace

AuthenticatedBus::AuthenticatedBus(std::unique_ptr<bus::Bus> inner, std::optional<RigKey> key,
                                   VerifierConfig config, std::function<int64_t()> now_utime)
    : inner_(std::move(inner)),
      now_(now_utime ? std::move(now_utime) : std::function<int64_t()>(realtime_utime)) {
  if (key) {
    signer_ = std::make_unique<Signer>(*key);
    verifier_ = std::make_unique<Verifier>(*key, config);
  }
  for (Verdict v : {Verdict::kMissing, Verdict::kWrongKey, Verdict::kBadMac, Verdict::kStale,
                    Verdict::kReplayed})
    drops_.add(counter_name(v), 0);  // every reason on STATUS from the start, 0 included
}

bool AuthenticatedBus::publish(const std::string& channel, std::span<const uint8_t> bytes) {
  if (!signer_) return inner_->publish(channel, bytes);
  // publish() may be called from any thread: a buffer per thread, grown once and reused.
  thread_local std::vector<uint8_t> signed_bytes;
  if (signed_bytes.size() < bytes.size() + kTrailerSize)
    signed_bytes.resize(bytes.size() + kTrailerSize);
  if (!bytes.empty()) std::memcpy(signed_bytes.data(), bytes.data(), bytes.size());
  signer_->sign(channel, bytes.data(), bytes.size(), now_(), signed_bytes.data() + bytes.size());
  return inner_->publish(channel, {signed_bytes.data(), bytes.size() + kTrailerSize});
}

bus::Subscription AuthenticatedBus::subscribe(const std::string& channel, bus::Handler handler,
                                              int queue_capacity) {
  return inner_->subscribe(
      channel,
      [this, handler = std::move(handler)](std::span<const uint8_t> bytes,
                                           const std::string& name) {
        if (!verifier_) {
          handler(bytes.first(strip_trailer(bytes.data(), bytes.size())), name);
          return;
        }
        const Verified r = verifier_->verify(name, bytes.data(), bytes.size(), now_());
        if (r.verdict != Verdict::kOk) {
          const std::string_view reason = counter_name(r.verdict);
          drops_.add(reason);
          // The first of each reason at warn (a second rig on the group, a wrong key file), the
          // rest at debug.
          if (drops_.get(reason) == 1)
            HULLPOSE_LOG(Auth, Warn) << name << ": dropped a message of " << bytes.size()
                                     << " bytes (" << reason << "); further ones are counted";
          else
            HULLPOSE_LOG(Auth, Debug)
                << name << ": dropped a message of " << bytes.size() << " bytes (" << reason << ")";
          return;
        }
        handler(bytes.first(r.message_size), name);
      },
      queue_capacity);
}

}  // namespace hullpose::auth
