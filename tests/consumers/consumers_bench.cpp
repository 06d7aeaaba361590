// consumers_bench: the latency the consumers add beyond SKELETON (make bench, via
// tools/bench/peers/consumers_latency.sh). It publishes N skeletons at --rate over real LCM and
// timestamps (monotonic clock, one process) each one's arrival at: a plain LCM subscriber (the
// baseline: when SKELETON is there for anyone), a WebSocket client of hullpose-web, an OSC
// server receiving hullpose-stream's VMC bundles and a TCP client of its BVH lines. Added
// latency = consumer arrival - baseline arrival, per frame; prints JSON lines (p50 as
// median_ms, p99, max). --only NAME measures one consumer (the others are not connected), so
// that consumers never compete with each other for the cores (consumers_latency.sh runs one
// process per pass). Beside the figures, what tells cost from noise: the consumer process's CPU
// time per frame and the time its threads sat runnable but waiting for a core (--pid,
// /proc/PID/task/*/schedstat), its involuntary context switches, this process's own, and the
// load average before and after.
#include <lo/lo.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/msg/wire.hpp"
#include "hullpose/skeleton_io/asio.hpp"
#include "hullpose/skeleton_io/take.hpp"
#include "hullpose/synth/motion.hpp"
#include "skeleton_pacer.hpp"

namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

struct Arrivals {
  std::mutex m;
  std::vector<int64_t> at;  // by frame index, 0 = never
  std::atomic<int64_t> count{0};
  explicit Arrivals(size_t n) : at(n, 0) {}
  void mark(size_t k) { mark_at(k, hullpose::monotonic_us()); }
  void mark_at(size_t k, int64_t now) {
    std::lock_guard<std::mutex> lock(m);
    if (k < at.size() && at[k] == 0) at[k] = now;
    ++count;
  }
};

int on_vmc_ok(const char*, const char*, lo_arg**, int, lo_message, void* user) {
  auto* a = static_cast<Arrivals*>(user);
  a->mark(static_cast<size_t>(
      a->count.load()));  // k-th bundle = k-th skeleton (all valid, none lost on loopback)
  return 0;
}

// What the scheduler did to a process: on-CPU and runnable-waiting time of all its threads
// (nanoseconds, schedstat) and involuntary context switches (preemptions).
struct SchedSample {
  double cpu_ms = 0, wait_ms = 0;
  int64_t preempted = 0;
};
SchedSample sched_sample(long pid) {
  SchedSample s;
  std::error_code ec;
  const std::filesystem::path tasks = "/proc/" + std::to_string(pid) + "/task";
  for (const auto& t : std::filesystem::directory_iterator(tasks, ec)) {
    std::ifstream stat(t.path() / "schedstat");
    double run_ns = 0, wait_ns = 0;
    if (stat >> run_ns >> wait_ns) {
      s.cpu_ms += run_ns / 1e6;
      s.wait_ms += wait_ns / 1e6;
    }
    std::ifstream status(t.path() / "status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("nonvoluntary_ctxt_switches:", 0) == 0)
        s.preempted += std::stoll(line.substr(line.find(':') + 1));
  }
  return s;
}
double load1() {
  std::ifstream in("/proc/loadavg");
  double l = -1;
  in >> l;
  return l;
}

double pct(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(std::max(
                                      0.0, std::ceil(q * static_cast<double>(v.size())) - 1)))];
}

}  // namespace

int run(int argc, const char* const* argv) {
  std::string url, only, suffix;
  long long pid = 0;
  int web_port = 0, vmc_port = 0, bvh_port = 0;
  long long frames = 300, warm = 10;
  double rate = 30;
  hullpose::cli::CommandLine cl(
      "usage: consumers_bench --lcm-url URL [--web-port P] [--vmc-port P] [--bvh-port P] "
      "[--only web|vmc|bvh_tcp --pid CONSUMER_PID] [--frames 300] [--rate 30] [--name-suffix S]\n");
  cl.option("--lcm-url", url)
      .option("--web-port", web_port)
      .option("--vmc-port", vmc_port)
      .option("--bvh-port", bvh_port)
      .option("--frames", frames)
      .option("--rate", rate)
      .option("--only", only)
      .option("--pid", pid)
      .option("--name-suffix", suffix);
  if (!cl.parse(argc, argv)) return 0;
  HULLPOSE_THROW_UNLESS(only.empty() || only == "web" || only == "vmc" || only == "bvh_tcp",
                        "--only must be web, vmc or bvh_tcp, got '" << only << "'");
  const auto measured = [&](const char* name) { return only.empty() || only == name; };
  const auto n = static_cast<size_t>(frames);
  Arrivals direct(n), web(n), vmc(n), bvh(n);

  const auto bus = hullpose::bus::open_bus(url);
  hullpose_msg::skeleton_t seen;
  const auto baseline =
      bus->subscribe("SKELETON", [&](std::span<const uint8_t> bytes, const std::string&) {
        if (hullpose::wire::decode(bytes, seen)) direct.mark(static_cast<size_t>(seen.trigger_seq));
      });
  std::atomic<bool> stop{false};
  std::thread lcm_thread([&] {
    while (!stop) bus->handle(50);
  });

  lo_server_thread osc = nullptr;
  if (measured("vmc")) {
    osc = lo_server_thread_new(std::to_string(vmc_port).c_str(), nullptr);
    HULLPOSE_THROW_UNLESS(osc, "cannot listen for OSC on port " << vmc_port);
    lo_server_thread_add_method(osc, "/VMC/Ext/OK", nullptr, on_vmc_ok, &vmc);
    lo_server_thread_start(osc);
  }

  asio::io_context io;
  namespace websocket = boost::beast::websocket;
  websocket::stream<tcp::socket> ws(io);
  std::thread ws_thread, bvh_thread;
  if (measured("web")) {
    ws.next_layer().connect(
        {asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(web_port)});
    ws.handshake("127.0.0.1", "/ws");
  }
  if (measured("web"))
    ws_thread = std::thread([&] {
      boost::beast::flat_buffer buf;
      boost::system::error_code ec;
      while (!stop) {
        ws.read(buf, ec);
        if (ec) break;
        const int64_t now = hullpose::monotonic_us();
        const auto j =
            nlohmann::json::parse(boost::beast::buffers_to_string(buf.data()), nullptr, false);
        buf.clear();
        if (j.is_object() && j.value("type", "") == "skeleton")
          web.mark_at(j["seq"].get<size_t>(), now);
      }
    });
  tcp::socket bvh_socket(io);
  if (measured("bvh_tcp")) {
    bvh_socket.connect(
        {asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(bvh_port)});
    bvh_socket.set_option(tcp::no_delay(true));
  }
  if (measured("bvh_tcp"))
    bvh_thread = std::thread([&] {
      asio::streambuf buf;
      boost::system::error_code ec;
      std::string line;
      while (!stop) {
        asio::read_until(bvh_socket, buf, '\n', ec);
        if (ec) break;
        std::istream in(&buf);
        std::getline(in, line);
        bvh.mark(static_cast<size_t>(bvh.count.load()));
      }
    });
  std::this_thread::sleep_for(
      std::chrono::milliseconds(500));  // all subscribers joined (set-up, not measured)

  const auto m = hullpose::synth::make_builtin_motion("walk", {});
  hullpose::skeleton_io::SkeletonFrame f;
  f.valid = true;
  f.confidence.fill(1.f);
  hullpose::consumers_test::SkeletonPacer pacer(*bus, "bench", rate);
  const double load_before = load1();
  const SchedSample consumer0 = pid > 0 ? sched_sample(pid) : SchedSample{},
                    self0 = sched_sample(getpid());
  for (size_t k = 0; k < n; ++k) {
    m->sample(static_cast<double>(k) / rate, f.joints);
    pacer.publish(static_cast<int64_t>(k), f);
    pacer.wait_next();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // stragglers
  const SchedSample consumer1 = pid > 0 ? sched_sample(pid) : SchedSample{},
                    self1 = sched_sample(getpid());
  const double load_after = load1();
  stop = true;
  boost::system::error_code ec;
  ws.next_layer().shutdown(tcp::socket::shutdown_both, ec);
  bvh_socket.shutdown(tcp::socket::shutdown_both, ec);
  if (ws_thread.joinable()) ws_thread.join();
  if (bvh_thread.joinable()) bvh_thread.join();
  lcm_thread.join();
  if (osc) lo_server_thread_free(osc);

  for (auto [name, arrivals] :
       {std::pair<const char*, Arrivals*>{"web", &web}, {"vmc", &vmc}, {"bvh_tcp", &bvh}}) {
    if (!measured(name)) continue;
    std::vector<double> added;
    int64_t lost = 0;
    for (size_t k = static_cast<size_t>(warm); k < n; ++k) {
      if (!direct.at[k] || !arrivals->at[k]) {
        ++lost;
        continue;
      }
      added.push_back(static_cast<double>(arrivals->at[k] - direct.at[k]) / 1000.0);
    }
    std::printf(
        "%s\n",
        nlohmann::json{
            {"name", std::string("consumers_added_latency_") + name + "_30hz" + suffix},
            {"median_ms", pct(added, 0.5)},
            {"p99_ms", pct(added, 0.99)},
            {"max_ms", added.empty() ? 0 : *std::max_element(added.begin(), added.end())},
            {"n", added.size()},
            {"lost", lost},
            {"rate_hz", rate},
            {"baseline", "arrival of SKELETON at a plain LCM subscriber in the same process"},
            // Cost vs noise: CPU the consumer process spent per frame, and how long its threads
            // (and this process's) waited runnable for a core over the run.
            {"consumer_cpu_us_per_frame",
             pid > 0
                 ? std::round((consumer1.cpu_ms - consumer0.cpu_ms) * 1000 / static_cast<double>(n))
                 : -1},
            {"consumer_runqueue_wait_ms",
             pid > 0 ? std::round(consumer1.wait_ms - consumer0.wait_ms) : -1},
            {"consumer_preempted", pid > 0 ? consumer1.preempted - consumer0.preempted : -1},
            {"bench_cpu_ms", std::round(self1.cpu_ms - self0.cpu_ms)},
            {"bench_runqueue_wait_ms", std::round(self1.wait_ms - self0.wait_ms)},
            {"load1_before", load_before},
            {"load1_after", load_after},
            {"cpus", std::thread::hardware_concurrency()}}
            .dump()
            .c_str());
  }
  return 0;
}

int main(int argc, char** argv) {
  return hullpose::run_tool("consumers_bench", argc, argv, run);
}
