#pragma once
// The bus of a rig with a key (docs/messages.md, "Authentication"): wraps the LCM bus that
// bus::open_bus opens, signs every message published and checks every message received before
// any handler sees it; what fails the check is dropped and counted by reason (drops()). Without
// a key it signs nothing, checks nothing and only strips trailers, so an open receiver reads an
// authenticated rig's messages too. Components never see trailers.
#include <memory>
#include <optional>

#include "hullpose/auth/message_auth.hpp"
#include "hullpose/common/bus.hpp"
#include "hullpose/common/counters.hpp"

namespace hullpose::auth {

class AuthenticatedBus final : public bus::Bus {
 public:
  // now_utime: the clock of sent_utime and of the time check (tests inject one).
  AuthenticatedBus(std::unique_ptr<bus::Bus> inner, std::optional<RigKey> key,
                   VerifierConfig config = {}, std::function<int64_t()> now_utime = {});

  bool publish(const std::string& channel, std::span<const uint8_t> bytes) override;
  [[nodiscard]] bus::Subscription subscribe(const std::string& channel, bus::Handler handler,
                                            int queue_capacity = 30) override;
  bool handle(int timeout_ms) override { return inner_->handle(timeout_ms); }
  int fd() const override { return inner_->fd(); }
  const std::string& url() const override { return inner_->url(); }
  std::vector<std::pair<std::string, int64_t>> drops() const override { return drops_.snapshot(); }

  bool authenticated() const { return signer_ != nullptr; }

 private:
  std::unique_ptr<bus::Bus> inner_;
  std::unique_ptr<Signer> signer_;      // null without a key
  std::unique_ptr<Verifier> verifier_;  // null without a key
  std::function<int64_t()> now_;
  Counters drops_;
};

}  // namespace hullpose::auth
