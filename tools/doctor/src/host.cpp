#include "hullpose/doctor/host.hpp"

#include <libcamera/libcamera.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/timex.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <gpiod.hpp>
#include <sstream>

namespace hullpose::doctor {
namespace fs = std::filesystem;

Host::Host(fs::path root) : root_(std::move(root)) {}

fs::path Host::at(const std::string& absolute) const {
  return root_ == "/" ? fs::path(absolute) : root_ / fs::path(absolute).relative_path();
}

std::optional<std::string> Host::read(const std::string& absolute) const {
  std::ifstream f(at(absolute), std::ios::binary);
  if (!f) return std::nullopt;
  std::ostringstream s;
  s << f.rdbuf();
  if (f.bad()) return std::nullopt;
  return s.str();
}

bool Host::exists(const std::string& absolute) const {
  std::error_code ec;
  return fs::exists(at(absolute), ec);
}

std::vector<std::string> Host::list(const std::string& absolute) const {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(at(absolute), ec), end; !ec && it != end; it.increment(ec))
    names.push_back(it->path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> Host::processes() const {
  std::vector<std::string> comms;
  for (const std::string& pid : list("/proc")) {
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    if (auto comm = read("/proc/" + pid + "/comm")) {
      comm->erase(std::find(comm->begin(), comm->end(), '\n'), comm->end());
      comms.push_back(*comm);
    }
  }
  return comms;
}

std::optional<unsigned> Host::interface_flags(const std::string& iface) const {
  if (root_ != "/") {
    const auto text = read("/sys/class/net/" + iface + "/flags");
    if (!text) return std::nullopt;
    return static_cast<unsigned>(std::stoul(*text, nullptr, 16));
  }
  // sysfs shows the network namespace it was mounted in; the ioctl shows ours.
  ifreq req{};
  if (iface.size() >= sizeof(req.ifr_name)) return std::nullopt;
  std::memcpy(req.ifr_name, iface.c_str(), iface.size());
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return std::nullopt;
  const int r = ::ioctl(fd, SIOCGIFFLAGS, &req);
  ::close(fd);
  if (r < 0) return std::nullopt;
  return static_cast<unsigned>(static_cast<unsigned short>(req.ifr_flags));
}

ClockState Host::clock() const {
  ClockState s;
  if (root_ != "/") {
    s.error = "the kernel clock is only probed on the real root";
    return s;
  }
  timex tx{};  // modes 0: read only
  if (::adjtimex(&tx) < 0) {
    s.error = std::string("adjtimex: ") + std::strerror(errno);
    return s;
  }
  s.synchronised = (tx.status & STA_UNSYNC) == 0;
  s.max_error_us = tx.maxerror;
  return s;
}

namespace {
std::string chip_path_spec(const std::string& chip) {
  if (chip.rfind("/dev/", 0) == 0) return chip;
  if (!chip.empty() && chip.find_first_not_of("0123456789") == std::string::npos)
    return "/dev/gpiochip" + chip;
  if (chip.rfind("gpiochip", 0) == 0) return "/dev/" + chip;
  return {};  // a label
}
}  // namespace

GpioChip Host::gpio_chip(const std::string& chip) const {
  GpioChip c;
  for (const std::string& n : list("/dev"))
    if (n.rfind("gpiochip", 0) == 0) c.present.push_back(n);
  const std::string path = chip_path_spec(chip);
  if (root_ != "/" && path.empty()) {
    c.error = "a chip label is only looked up on the real root";
    return c;
  }
  if (!path.empty() && !exists(path)) {
    c.error = at(path).string() + " does not exist";
    return c;
  }
  try {
    gpiod::chip g(path.empty() ? chip : at(path).string(),
                  path.empty() ? gpiod::chip::OPEN_LOOKUP : gpiod::chip::OPEN_BY_PATH);
    c.found = true;
    c.name = g.name();
    c.label = g.label();
    c.num_lines = g.num_lines();
  } catch (const std::exception& e) {
    c.error = path.empty()
                  ? "no chip labelled '" + chip + "' (" + e.what() + ")"
                  : at(path).string() + " is not a GPIO character device (" + e.what() + ")";
  }
  return c;
}

GpioLine Host::gpio_line(const std::string& chip, unsigned offset) const {
  GpioLine l;
#if HULLPOSE_DOCTOR_LIBGPIOD
  const std::string path = chip_path_spec(chip);
  try {
    gpiod::chip g(path.empty() ? chip : at(path).string(),
                  path.empty() ? gpiod::chip::OPEN_LOOKUP : gpiod::chip::OPEN_BY_PATH);
    const gpiod::line line = g.get_line(offset);
    l.used = line.is_used();
    l.consumer = line.consumer();
  } catch (const std::exception& e) {
    l.used = true;
    l.consumer = std::string("(line info unreadable: ") + e.what() + ")";
  }
#else
  (void)chip, (void)offset;
#endif
  return l;
}

CameraList Host::cameras() const {
  CameraList list;
  if (root_ != "/") {
    list.error = "libcamera is only asked on the real root";
    return list;
  }
#if HULLPOSE_DOCTOR_LIBCAMERA
  // libcamera logs every pipeline handler it tries at INFO; the doctor's own message says enough.
  ::setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", 0);
  libcamera::CameraManager manager;
  if (const int r = manager.start(); r < 0) {
    list.error = "libcamera's CameraManager failed to start (error " + std::to_string(r) + ")";
    return list;
  }
  list.probed = true;
  for (const auto& camera : manager.cameras()) list.ids.push_back(camera->id());
  manager.stop();
#else
  list.error = "this build of hullpose-doctor has no libcamera";
#endif
  return list;
}

}  // namespace hullpose::doctor
