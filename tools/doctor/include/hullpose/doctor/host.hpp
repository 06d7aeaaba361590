#pragma once
// What hullpose-doctor knows of the machine it checks. Files (procfs, sysfs, /etc, /dev) are read
// under an injectable root, so tests build a fake tree; what no file shows — the kernel clock's
// synchronisation state, a GPIO chip's lines, libcamera's camera list — comes from virtual
// probes whose real backends (adjtimex, libgpiod, libcamera) are used in production and which
// tests replace. The real probes only look at the machine itself when the root is "/".
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hullpose::doctor {

struct ClockState {
  bool synchronised =
      false;  // the kernel's STA_UNSYNC is clear (chrony, ntpd, timesyncd, phc2sys set it)
  long max_error_us = 0;  // the kernel's maxerror estimate
  std::string error;      // the probe failed: why (then `synchronised` means nothing)
};

struct GpioLine {
  bool used = false;     // requested by some process or by the kernel (a driver, a hog)
  std::string consumer;  // who holds it
};

struct GpioChip {
  bool found = false;
  std::string error;  // not found / not openable: why
  std::string name;   // gpiochipN
  std::string label;  // e.g. pinctrl-rp1
  unsigned num_lines = 0;
  std::vector<std::string> present;  // the chips this host has (for the message when not found)
};

struct CameraList {
  bool probed =
      false;  // false: the probe cannot look (another root, no libcamera): `error` says why
  std::string error;
  std::vector<std::string> ids;
};

class Host {
 public:
  explicit Host(std::filesystem::path root = "/");
  virtual ~Host() = default;
  Host(const Host&) = delete;
  Host& operator=(const Host&) = delete;

  const std::filesystem::path& root() const { return root_; }
  // An absolute path on the checked machine, under the root.
  std::filesystem::path at(const std::string& absolute) const;
  // The file's text, or nothing when it cannot be read.
  std::optional<std::string> read(const std::string& absolute) const;
  bool exists(const std::string& absolute) const;
  // Entry names of a directory, sorted; empty when it does not exist.
  std::vector<std::string> list(const std::string& absolute) const;
  // The command names (comm) of every process in /proc.
  std::vector<std::string> processes() const;

  // An interface's flags (IFF_UP, IFF_MULTICAST, ...): SIOCGIFFLAGS in this process's network
  // namespace on the real root, /sys/class/net/IF/flags under another; nothing if unknown.
  virtual std::optional<unsigned> interface_flags(const std::string& iface) const;
  virtual ClockState clock() const;
  // chip: a name (gpiochip0), a path (/dev/gpiochip0), a label (pinctrl-rp1) or a number, as
  // libgpiod's lookup.
  virtual GpioChip gpio_chip(const std::string& chip) const;
  // Only valid for a chip `gpio_chip` found.
  virtual GpioLine gpio_line(const std::string& chip, unsigned offset) const;
  virtual CameraList cameras() const;

 private:
  std::filesystem::path root_;
};

}  // namespace hullpose::doctor
