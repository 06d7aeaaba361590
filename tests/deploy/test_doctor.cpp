// hullpose-doctor's start-up checks: each failing condition, produced in a fake root (procfs,
// sysfs, /dev, /etc) or a network namespace of its own, gives its message and its fix.
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "hullpose/auth/rig_key.hpp"
#include "hullpose/doctor/checks.hpp"
#include "hullpose/synth/rig_gen.hpp"

namespace fs = std::filesystem;
using namespace hullpose;
using namespace hullpose::doctor;

namespace {

// /proc/net/route words as a little-endian kernel writes them.
constexpr const char* kRouteHeader =
    "Iface\tDestination\tGateway \tFlags\tRefCnt\tUse\tMetric\tMask\t\tMTU\tWindow\tIRTT\n";
constexpr const char* kRouteLan =
    "eth0\t0001A8C0\t00000000\t0001\t0\t0\t0\t00FFFFFF\t0\t0\t0\n";  // 192.168.1.0/24
constexpr const char* kRouteMulticast =
    "eth0\t000000E0\t00000000\t0001\t0\t0\t0\t000000F0\t0\t0\t0\n";  // 224.0.0.0/4
constexpr const char* kRouteLoMulticast =
    "lo\t000000E0\t00000000\t0001\t0\t0\t0\t000000F0\t0\t0\t0\n";

// A healthy camera board + fusion host in a directory; each test breaks one thing.
struct FakeRoot {
  fs::path root;
  bool keyed = true;  // camera3.yaml names the rig key (lcm.rig_key)
  explicit FakeRoot(const std::string& name) {
    root =
        fs::temp_directory_path() / ("hullpose-doctor-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(root);
    write("/proc/sys/net/core/rmem_max", "8388608\n");
    write("/proc/sys/net/core/rmem_default", "212992\n");
    write("/proc/net/route", std::string(kRouteHeader) + kRouteLan + kRouteMulticast);
    write("/sys/class/net/eth0/flags", "0x1003\n");
    write("/proc/17/comm", "chronyd\n");
    write("/proc/1/comm", "systemd\n");
    write("/sys/module/imx296/parameters/trigger_mode", "0\n");
    write("/etc/hullpose/hullpose.conf",
          "# rig-wide\nHULLPOSE_LCM_URL=\"udpm://239.255.76.67:7667?ttl=1&recv_buf_size=4194304\"\n"
          "HULLPOSE_RIG=/etc/hullpose/"
          "rig.yaml\nHULLPOSE_RIG_ID=thesis8\nHULLPOSE_TRIGGER_LINE=gpiod:gpiochip0:17\n"
          "HULLPOSE_RIG_KEY=/etc/hullpose/rig.key\n");
    auth::RigKey::generate().save((root / "etc/hullpose/rig.key").string());
    camera("ttl=1&recv_buf_size=4194304", "libcamera", "external_trigger: true");
    save_rig(synth::make_ring_rig({}), root / "etc/hullpose/rig.yaml");
  }
  ~FakeRoot() { fs::remove_all(root); }
  void write(const std::string& path, const std::string& text) const {
    const fs::path p = root / fs::path(path).relative_path();
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
  }
  void camera(const std::string& url_options, const std::string& source,
              const std::string& source_extra) const {
    write("/etc/hullpose/camera3.yaml",
          "%YAML:1.0\ncamera_id: 3\nrig_file: rig.yaml\nsource: { type: " + source +
              (source_extra.empty() ? "" : ", " + source_extra) +
              " }\nbgs: { method: sobs, learn_frames: 30 }\nlcm: { url: "
              "\"udpm://239.255.76.67:7667?" +
              url_options + "\"" + (keyed ? ", rig_key: rig.key" : "") +
              " }\ntrigger:\n  edges: gpiod\n  chip: gpiochip0\n  line: 17\n");
  }
};

// The probes no file can fake: the kernel clock, the GPIO chip's lines, libcamera's list.
struct FakeHost : Host {
  using Host::Host;
  ClockState clock_state{true, 1200, ""};
  bool chip_found = true;
  unsigned num_lines = 54;
  GpioLine line{false, ""};
  std::vector<std::string> camera_ids{"/base/axi/pcie@120000/rp1/i2c@88000/imx296@1a"};
  ClockState clock() const override { return clock_state; }
  GpioChip gpio_chip(const std::string& chip) const override {
    if (!chip_found)
      return Host::gpio_chip(chip);  // the real libgpiod backend, under the fake root
    GpioChip c;
    c.found = true, c.name = "gpiochip0", c.label = "pinctrl-rp1", c.num_lines = num_lines;
    return c;
  }
  GpioLine gpio_line(const std::string&, unsigned) const override { return line; }
  CameraList cameras() const override { return {true, "", camera_ids}; }
};

std::map<std::string, Result> by_check(const Host& host, Role role = Role::kAll) {
  std::map<std::string, Result> out;
  for (const Result& r : run_checks(host, setup_from_etc(host, role))) out[r.check] = r;
  return out;
}

}  // namespace

TEST_CASE("a healthy board passes every check") {
  FakeRoot f("healthy");
  FakeHost host(f.root);
  const auto results = run_checks(host, setup_from_etc(host, Role::kAll));
  for (const Result& r : results) {
    INFO(r.check << ": " << r.message);
    CHECK(r.status == Status::kOk);
  }
  const auto by = by_check(host);
  for (const char* check :
       {"net.multicast_route", "net.multicast_ttl", "net.rmem", "clock.sync", "gpio.trigger_master",
        "camera.3", "camera.3.trigger_mode", "gpio.camera3", "rig.file", "rig.key"})
    CHECK(by.count(check) == 1);
}

TEST_CASE("net.core.rmem_max too small for the silhouette bursts") {
  FakeRoot f("rmem");
  f.write("/proc/sys/net/core/rmem_max", "212992\n");
  FakeHost host(f.root);
  const Result r = by_check(host, Role::kFusionHost)["net.rmem"];
  CHECK(r.status == Status::kFail);
  CHECK_THAT(r.message, Catch::Contains("425984 bytes") && Catch::Contains("8 cameras x 32 KiB"));
  CHECK_THAT(r.fix, Catch::Contains("sysctl -w net.core.rmem_max=4194304"));
  // Without recv_buf_size in the URL, LCM leaves the socket at rmem_default, whatever rmem_max
  // says.
  f.write("/proc/sys/net/core/rmem_max", "8388608\n");
  f.write(
      "/etc/hullpose/hullpose.conf",
      "HULLPOSE_LCM_URL=udpm://239.255.76.67:7667?ttl=1\nHULLPOSE_RIG=/etc/hullpose/rig.yaml\n");
  const Result d = by_check(host, Role::kFusionHost)["net.rmem"];
  CHECK(d.status == Status::kFail);
  CHECK_THAT(d.message, Catch::Contains("net.core.rmem_default=212992"));
}

TEST_CASE("no multicast route") {
  FakeRoot f("route");
  f.write("/proc/net/route", std::string(kRouteHeader));  // no default route either
  FakeHost host(f.root);
  const Result r = by_check(host)["net.multicast_route"];
  CHECK(r.status == Status::kFail);
  CHECK_THAT(r.message, Catch::Contains("no route to the LCM group 239.255.76.67"));
  CHECK_THAT(r.fix, Catch::Contains("ip route add 224.0.0.0/4 dev"));
  // A route through an interface that is down is as good as none.
  f.write("/proc/net/route", std::string(kRouteHeader) + kRouteMulticast);
  f.write("/sys/class/net/eth0/flags", "0x1002\n");
  const Result down = by_check(host)["net.multicast_route"];
  CHECK(down.status == Status::kFail);
  CHECK_THAT(down.message, Catch::Contains("eth0, which is down"));
}

TEST_CASE("multicast TTL 0 on a real LAN, but not on loopback") {
  FakeRoot f("ttl");
  f.camera("recv_buf_size=4194304", "libcamera",
           "external_trigger: true");  // no ttl: LCM's default 0
  FakeHost host(f.root);
  const Result r = by_check(host, Role::kCameraNode)["net.multicast_ttl"];
  CHECK(r.status == Status::kFail);
  CHECK_THAT(r.message, Catch::Contains("ttl=0") && Catch::Contains("through eth0"));
  CHECK_THAT(r.fix, Catch::Contains("?ttl=1"));
  f.write("/proc/net/route", std::string(kRouteHeader) + kRouteLoMulticast);
  CHECK(by_check(host, Role::kCameraNode)["net.multicast_ttl"].status == Status::kOk);
}

TEST_CASE("GPIO chip missing, not a chip, line missing, line busy") {
  FakeRoot f("gpio");
  FakeHost host(f.root);
  SECTION("no chip: the real libgpiod backend under the fake root") {
    host.chip_found = false;
    const Result r = by_check(host, Role::kCameraNode)["gpio.camera3"];
    CHECK(r.status == Status::kFail);
    CHECK_THAT(r.message,
               Catch::Contains("GPIO chip 'gpiochip0'") && Catch::Contains("chips here: none"));
    CHECK_THAT(r.fix, Catch::Contains("gpiodetect"));
  }
  SECTION("a file where the chip should be") {
    host.chip_found = false;
    f.write("/dev/gpiochip0", "");
    const Result r = by_check(host, Role::kCameraNode)["gpio.camera3"];
    CHECK(r.status == Status::kFail);
    CHECK_THAT(r.message, Catch::Contains("not a GPIO character device"));
  }
  SECTION("line beyond the chip") {
    host.num_lines = 16;
    const Result r = by_check(host, Role::kCameraNode)["gpio.camera3"];
    CHECK(r.status == Status::kFail);
    CHECK_THAT(r.message, Catch::Contains("has 16 lines") && Catch::Contains("line 17"));
  }
  SECTION("line held by someone else, or by hullpose itself") {
    host.line = {true, "gpio-shutdown"};
    const Result r = by_check(host, Role::kCameraNode)["gpio.camera3"];
    CHECK(r.status == Status::kFail);
    CHECK_THAT(r.message, Catch::Contains("busy, held by 'gpio-shutdown'"));
    host.line = {true, "hullpose-camera-node"};
    CHECK(by_check(host, Role::kCameraNode)["gpio.camera3"].status == Status::kOk);
  }
  SECTION("the trigger master's line") {
    host.line = {true, "sysfs"};
    const Result r = by_check(host, Role::kTriggerMaster)["gpio.trigger_master"];
    CHECK(r.status == Status::kFail);
    CHECK_THAT(r.message, Catch::Contains("held by 'sysfs'"));
  }
}

TEST_CASE("camera absent, no external-trigger parameter, V4L2 device absent") {
  FakeRoot f("camera");
  FakeHost host(f.root);
  host.camera_ids.clear();
  const Result r = by_check(host, Role::kCameraNode)["camera.3"];
  CHECK(r.status == Status::kFail);
  CHECK_THAT(r.message, Catch::Contains("camera absent: libcamera lists no cameras"));
  CHECK_THAT(r.fix, Catch::Contains("dtoverlay=imx296"));
  fs::remove_all(f.root / "sys/module/imx296");
  const Result t = by_check(host, Role::kCameraNode)["camera.3.trigger_mode"];
  CHECK(t.status == Status::kFail);
  CHECK_THAT(t.message, Catch::Contains("no loaded sensor driver has a trigger_mode"));
  f.camera("ttl=1&recv_buf_size=4194304", "v4l2", "device: /dev/video4");
  const Result v = by_check(host, Role::kCameraNode)["camera.3"];
  CHECK(v.status == Status::kFail);
  CHECK_THAT(v.message, Catch::Contains("V4L2 device /dev/video4"));
  f.write("/dev/video4", "");
  CHECK(by_check(host, Role::kCameraNode)["camera.3"].status == Status::kOk);
}

TEST_CASE("clock not synchronised") {
  FakeRoot f("clock");
  FakeHost host(f.root);
  host.clock_state = {false, 16000000, ""};
  const Result r = by_check(host)["clock.sync"];
  CHECK(r.status == Status::kWarn);
  CHECK_THAT(r.message,
             Catch::Contains("chronyd running, but the kernel clock is not synchronised"));
  CHECK_THAT(r.fix, Catch::Contains("chronyc tracking"));
  fs::remove_all(f.root / "proc/17");
  const Result none = by_check(host)["clock.sync"];
  CHECK(none.status == Status::kWarn);
  CHECK_THAT(none.fix, Catch::Contains("apt install chrony"));
  f.write("/proc/99/comm", "ptp4l\n");
  CHECK_THAT(by_check(host)["clock.sync"].message,
             Catch::Contains("ptp4l runs but phc2sys does not"));
}

TEST_CASE("rig file missing or without this camera") {
  FakeRoot f("rig");
  FakeHost host(f.root);
  f.camera("ttl=1&recv_buf_size=4194304", "libcamera", "");
  fs::remove(f.root / "etc/hullpose/rig.yaml");
  const Result r = by_check(host, Role::kFusionHost)["rig.file"];
  CHECK(r.status == Status::kFail);
  CHECK_THAT(r.message, Catch::Contains("rig file /etc/hullpose/rig.yaml is missing"));
  CHECK_THAT(r.fix, Catch::Contains("hullpose-calibrate"));
  auto spec = synth::RingRigSpec{};
  spec.ring_cameras = 2, spec.ceiling = false;
  save_rig(synth::make_ring_rig(spec), f.root / "etc/hullpose/rig.yaml");
  CHECK_THAT(by_check(host, Role::kCameraNode)["rig.file"].message,
             Catch::Contains("has no camera 3"));
}

TEST_CASE("the trigger master announces another rig id than the rig file's") {
  FakeRoot f("rigid");
  f.write("/etc/hullpose/trigger-master.conf", "HULLPOSE_RIG_ID=lab\n");  // a later file wins
  FakeHost host(f.root);
  const Result r = by_check(host, Role::kTriggerMaster)["rig.id"];
  CHECK(r.status == Status::kFail);
  CHECK_THAT(r.message, Catch::Contains("HULLPOSE_RIG_ID=lab") && Catch::Contains("rig 'thesis8'"));
  CHECK_THAT(r.fix, Catch::Contains("HULLPOSE_RIG_ID=thesis8"));
}

TEST_CASE("rig key missing, readable by others, or none configured") {
  FakeRoot f("rigkey");
  FakeHost host(f.root);
  const fs::path key = f.root / "etc/hullpose/rig.key";
  const Result good = by_check(host, Role::kFusionHost)["rig.key"];
  CHECK(good.status == Status::kOk);
  CHECK_THAT(good.message, Catch::Contains("key id "));

  fs::permissions(key, fs::perms::group_read | fs::perms::others_read, fs::perm_options::add);
  for (const Role role : {Role::kFusionHost, Role::kCameraNode}) {
    const Result r = by_check(host, role)["rig.key"];  // the camera's from its config's lcm.rig_key
    CHECK(r.status == Status::kFail);
    CHECK_THAT(r.message, Catch::Contains("permissions 0644"));
    CHECK_THAT(r.fix, Catch::Contains("install -o hullpose -g hullpose -m 600 rig.key"));
  }
  fs::remove(key);
  const Result missing = by_check(host, Role::kFusionHost)["rig.key"];
  CHECK(missing.status == Status::kFail);
  CHECK_THAT(missing.message, Catch::Contains("rig key /etc/hullpose/rig.key is missing"));
  CHECK_THAT(missing.fix, Catch::Contains("hullpose-rig-key --output rig.key"));
  CHECK(by_check(host, Role::kCameraNode)["rig.key"].status == Status::kFail);

  f.write("/etc/hullpose/hullpose.conf", "HULLPOSE_RIG=/etc/hullpose/rig.yaml\n");
  f.keyed = false;
  f.camera("ttl=1&recv_buf_size=4194304", "libcamera", "");
  for (const Role role : {Role::kAll, Role::kCameraNode}) {
    const Result open = by_check(host, role)["rig.key"];
    CHECK(open.status == Status::kWarn);
    CHECK_THAT(open.message, Catch::Contains("not authenticated"));
  }
}

TEST_CASE("the shipped and the board profiles' camera configs load") {
  // Each beside a rig key, as on a board (/etc/hullpose/rig.key; lcm.rig_key: rig.key).
  const fs::path src = HULLPOSE_SOURCE_DIR;
  const fs::path dir =
      fs::temp_directory_path() / ("hullpose-doctor-shipped-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  auth::RigKey::generate().save((dir / "rig.key").string());
  for (const char* file :
       {"deploy/config/camera0.yaml", "deploy/boards/rpi5-global-shutter/camera.yaml",
        "deploy/boards/rpi-hq-free-running/camera.yaml"}) {
    fs::copy_file(src / file, dir / "camera.yaml", fs::copy_options::overwrite_existing);
    const CameraSetup c = load_camera(Host("/"), (dir / "camera.yaml").string());
    INFO(file);
    CHECK(c.error.empty());
    CHECK(c.source == "libcamera");
    CHECK(c.trigger_edges == "gpiod:pinctrl-rp1:17");
    CHECK(c.rig_key == (dir / "rig.key").string());
  }
  fs::remove_all(dir);
}

TEST_CASE("LCM URLs: udpm options, other providers") {
  const auto u = parse_udpm("udpm://239.255.76.70:7700?ttl=2&recv_buf_size=1048576");
  REQUIRE(u);
  CHECK(u->group == "239.255.76.70");
  CHECK(u->port == 7700);
  CHECK(u->ttl == 2);
  CHECK(u->recv_buf_size == 1048576);
  CHECK(parse_udpm("")->ttl == 0);
  CHECK_FALSE(parse_udpm("memq://"));
  CHECK_THROWS_WITH(parse_role("camera"), Catch::Contains("--role must be"));
}

TEST_CASE("the real procfs in a network namespace without routes, then with the multicast route") {
  // A child process unshares the network (root only), so this test never touches the host's.
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::close(fds[0]);
    const auto route_status = [] {
      Setup s;
      s.role = Role::kCameraNode;
      s.lcm_url = "udpm://239.255.76.67:7667?ttl=0";
      for (const Result& r : run_checks(Host("/"), s))
        if (r.check == "net.multicast_route") return r.status == Status::kOk ? 'o' : 'f';
      return '?';
    };
    char out[3] = {'s', 's', '\n'};
    if (::unshare(CLONE_NEWNET) == 0) {
      out[0] = route_status();
      const int rc =
          std::system("ip link set lo up multicast on && ip route add 224.0.0.0/4 dev lo");
      out[1] = rc == 0 ? route_status() : 'e';
    }
    [[maybe_unused]] const ssize_t n = ::write(fds[1], out, 3);
    ::_exit(0);
  }
  ::close(fds[1]);
  char got[3] = {};
  REQUIRE(::read(fds[0], got, 3) == 3);
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (got[0] == 's') {
    WARN("unshare(CLONE_NEWNET) not permitted here (not root?): namespace case not run");
    return;
  }
  CHECK(got[0] == 'f');  // a fresh namespace: lo down, no routes
  CHECK(got[1] == 'o');  // lo up with 224.0.0.0/4
}
