#include "hullpose/firmware_sync/trigger_line.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>
#if HULLPOSE_HAVE_LIBGPIOD
#include <gpiod.hpp>
#endif

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/trigger_line_spec.hpp"

namespace hullpose::sync {
HULLPOSE_LOG_CATEGORY(Line, "trigger_line")

namespace {

#if HULLPOSE_HAVE_LIBGPIOD
class GpiodTriggerLine final : public TriggerLine {
 public:
  GpiodTriggerLine(const std::string& chip, unsigned offset)
      : name_("gpiod:" + chip + ":" + std::to_string(offset)) {
    try {
      chip_.open(chip, gpiod::chip::OPEN_LOOKUP);
      line_ = chip_.get_line(offset);
      line_.request({"hullpose-trigger-master", gpiod::line_request::DIRECTION_OUTPUT, 0}, 0);
    } catch (const std::exception& e) {
      HULLPOSE_THROW("trigger line "
                     << name_ << ": cannot open GPIO chip '" << chip << "' line " << offset << " ("
                     << e.what()
                     << "); on a machine without the trigger GPIO use --line wire:PATH or sim");
    }
  }
  int64_t set(bool high) override {
    line_.set_value(high ? 1 : 0);
    return -1;
  }
  std::string describe() const override { return name_; }

 private:
  std::string name_;
  gpiod::chip chip_;
  gpiod::line line_;
};
#endif

// The simulated wire: a SOCK_SEQPACKET listener; each connected node receives one 8-byte
// CLOCK_MONOTONIC nanosecond stamp per rising edge. Never blocks the pulse loop: new nodes are
// accepted without waiting and a node that cannot take the stamp is disconnected.
class WireTriggerLine final : public TriggerLine {
 public:
  explicit WireTriggerLine(const std::string& path) : path_(path) {
    sockaddr_un addr{};
    HULLPOSE_THROW_UNLESS(!path.empty() && path.size() < sizeof(addr.sun_path),
                          "trigger line wire:" << path << ": socket path empty or too long");
    listen_fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    HULLPOSE_THROW_UNLESS(listen_fd_ >= 0,
                          "trigger line wire:" << path << ": socket: " << std::strerror(errno));
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path.c_str(), path.size());
    ::unlink(path.c_str());
    if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
        ::listen(listen_fd_, 64) != 0) {
      const int err = errno;
      ::close(listen_fd_);
      HULLPOSE_THROW("trigger line wire:" << path << ": bind/listen: " << std::strerror(err));
    }
    clients_.reserve(kMaxClients);
  }
  ~WireTriggerLine() override {
    for (int fd : clients_) ::close(fd);
    ::close(listen_fd_);
    ::unlink(path_.c_str());
  }
  WireTriggerLine(const WireTriggerLine&) = delete;
  WireTriggerLine& operator=(const WireTriggerLine&) = delete;

  int64_t set(bool high) override {
    if (!high) return -1;
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    const int64_t stamp_ns = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
    accept_new();
    for (size_t i = 0; i < clients_.size();) {
      if (::send(clients_[i], &stamp_ns, sizeof(stamp_ns), MSG_DONTWAIT | MSG_NOSIGNAL) !=
          sizeof(stamp_ns)) {
        HULLPOSE_LOG(Line, Info) << "wire:" << path_ << ": node disconnected";
        ::close(clients_[i]);
        clients_[i] = clients_.back();
        clients_.pop_back();
      } else {
        ++i;
      }
    }
    return stamp_ns / 1000;
  }
  std::string describe() const override { return "wire:" + path_; }
  size_t wait_for_nodes(size_t nodes, int timeout_ms) override {
    const int64_t until = monotonic_us() + int64_t{timeout_ms} * 1000;
    accept_new();
    while (clients_.size() < nodes) {
      const int64_t left_ms = (until - monotonic_us()) / 1000;
      if (left_ms <= 0) break;
      pollfd p{listen_fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(std::min<int64_t>(left_ms, 1000))) > 0) accept_new();
    }
    return clients_.size();
  }

 private:
  static constexpr size_t kMaxClients = 256;
  void accept_new() {
    for (;;) {
      const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
      if (fd < 0) return;
      if (clients_.size() >= kMaxClients) {
        ::close(fd);
        continue;
      }
      clients_.push_back(fd);
    }
  }
  std::string path_;
  int listen_fd_ = -1;
  std::vector<int> clients_;
};

}  // namespace

std::unique_ptr<TriggerLine> open_trigger_line(const std::string& spec) {
  const TriggerLineSpec line = parse_trigger_line_spec(spec, "trigger line", true);
  switch (line.kind) {
    case TriggerLineSpec::Kind::kSim:
      return std::make_unique<SimTriggerLine>();
    case TriggerLineSpec::Kind::kWire:
      return std::make_unique<WireTriggerLine>(line.path);
    case TriggerLineSpec::Kind::kGpiod:
      break;
  }
#if HULLPOSE_HAVE_LIBGPIOD
  return std::make_unique<GpiodTriggerLine>(line.chip, line.offset);
#else
  throw_no_libgpiod(spec, "trigger line", "--line wire:PATH or sim");
#endif
}

}  // namespace hullpose::sync
