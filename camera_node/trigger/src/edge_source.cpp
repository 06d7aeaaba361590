#include "hullpose/camera_node/edge_source.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#if HULLPOSE_HAVE_LIBGPIOD
#include <gpiod.hpp>
#endif

#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/trigger_line_spec.hpp"

namespace hullpose::trigger {

namespace {

#if HULLPOSE_HAVE_LIBGPIOD
// libgpiod v1 line events. The kernel stamps them with CLOCK_MONOTONIC (Linux >= 5.7).
class GpiodEdgeSource final : public EdgeSource {
 public:
  GpiodEdgeSource(const std::string& chip, unsigned offset, const NodeClock& clock)
      : name_("gpiod:" + chip + ":" + std::to_string(offset)), clock_(clock) {
    try {
      chip_.open(chip, gpiod::chip::OPEN_LOOKUP);
      line_ = chip_.get_line(offset);
      line_.request({"hullpose-camera-node", gpiod::line_request::EVENT_RISING_EDGE, 0});
    } catch (const std::exception& e) {
      HULLPOSE_THROW("trigger input "
                     << name_ << ": cannot open GPIO chip '" << chip << "' line " << offset << " ("
                     << e.what()
                     << "); without the trigger GPIO use wire:PATH or a free-running camera");
    }
    fd_ = line_.event_get_fd();
    HULLPOSE_THROW_UNLESS(
        ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK) == 0,
        "trigger input " << name_ << ": cannot make the event descriptor non-blocking");
  }
  int fd() const override { return fd_; }
  bool read(int64_t& edge_us) override {
    for (;;) {
      if (!line_.event_wait(std::chrono::nanoseconds(0))) return false;
      const gpiod::line_event ev = line_.event_read();
      if (ev.event_type != gpiod::line_event::RISING_EDGE) continue;
      edge_us = ev.timestamp.count() / 1000 + clock_.offset();
      return true;
    }
  }
  std::string describe() const override { return name_; }

 private:
  std::string name_;
  NodeClock clock_;
  gpiod::chip chip_;
  gpiod::line line_;
  int fd_ = -1;
};
#endif

// The simulated wire: 8-byte CLOCK_MONOTONIC nanosecond stamps from the trigger master. If the
// master goes away, reconnects (at most every 200 ms) so a restarted master is picked up.
class WireEdgeSource final : public EdgeSource {
 public:
  // Waits up to connect_timeout_ms for the master's wire to appear (processes of a simulated rig
  // start in any order).
  WireEdgeSource(const std::string& path, const NodeClock& clock, int connect_timeout_ms)
      : path_(path), clock_(clock) {
    const int64_t until = monotonic_us() + int64_t{connect_timeout_ms} * 1000;
    while (!connect_wire() && monotonic_us() < until) ::usleep(50'000);
    HULLPOSE_THROW_UNLESS(
        fd_ >= 0, "trigger input wire:"
                      << path_ << ": cannot connect to the trigger master's wire ("
                      << std::strerror(errno)
                      << "); is hullpose-trigger-master --line wire:" << path_ << " running?");
  }
  ~WireEdgeSource() override {
    if (fd_ >= 0) ::close(fd_);
  }
  WireEdgeSource(const WireEdgeSource&) = delete;
  WireEdgeSource& operator=(const WireEdgeSource&) = delete;

  int fd() const override { return fd_; }
  bool read(int64_t& edge_us) override {
    if (fd_ < 0) {
      const int64_t now = monotonic_us();
      if (now - last_attempt_us_ < 200'000) return false;
      last_attempt_us_ = now;
      if (!connect_wire()) return false;
    }
    int64_t stamp_ns = 0;
    const ssize_t n = ::recv(fd_, &stamp_ns, sizeof(stamp_ns), MSG_DONTWAIT);
    if (n == sizeof(stamp_ns)) {
      edge_us = stamp_ns / 1000 + clock_.offset();
      return true;
    }
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
      ::close(fd_);
      fd_ = -1;
      last_attempt_us_ = monotonic_us();
    }
    return false;
  }
  std::string describe() const override { return "wire:" + path_; }

 private:
  bool connect_wire() {
    sockaddr_un addr{};
    if (path_.empty() || path_.size() >= sizeof(addr.sun_path)) {
      errno = ENAMETOOLONG;
      return false;
    }
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path_.c_str(), path_.size());
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    if (fd < 0) return false;
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
      const int err = errno;
      ::close(fd);
      errno = err;
      return false;
    }
    fd_ = fd;
    return true;
  }
  std::string path_;
  NodeClock clock_;
  int fd_ = -1;
  int64_t last_attempt_us_ = 0;
};

}  // namespace

std::unique_ptr<EdgeSource> open_edge_source(const std::string& spec, const NodeClock& clock,
                                             int connect_timeout_ms) {
  const TriggerLineSpec line = parse_trigger_line_spec(spec, "trigger input", false);
  if (line.kind == TriggerLineSpec::Kind::kWire)
    return std::make_unique<WireEdgeSource>(line.path, clock, connect_timeout_ms);
#if HULLPOSE_HAVE_LIBGPIOD
  return std::make_unique<GpiodEdgeSource>(line.chip, line.offset, clock);
#else
  throw_no_libgpiod(spec, "trigger input", "wire:PATH");
#endif
}

}  // namespace hullpose::trigger
