// consumers_bench: the latency the consumers add beyond SKELETON (make bench, via
// tools/bench/peers/consumers_latency.sh). It publishes N skeletons at --rate over real LCM and
// timestamps (monotonic clock, one process) each one's arrival at: a plain LCM subscriber (the
// baseline: when SKELETON is there for anyone), a WebSocket client of hullpose-web, an OSC
// server receiving hullpose-stream's VMC bundles and a TCP client of its BVH lines. Added
// latency = consumer arrival - baseline arrival, per frame; prints JSON lines (p50 as
// median_ms, p99, max).
#include <lo/lo.h>

#include <algorithm>
#include <atomic>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <nlohmann/json.hpp>
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

double pct(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(std::max(
                                      0.0, std::ceil(q * static_cast<double>(v.size())) - 1)))];
}

}  // namespace

int run(int argc, const char* const* argv) {
  std::string url;
  int web_port = 0, vmc_port = 0, bvh_port = 0;
  long long frames = 300, warm = 10;
  double rate = 30;
  hullpose::cli::CommandLine cl(
      "usage: consumers_bench --lcm-url URL --web-port P --vmc-port P --bvh-port P [--frames "
      "300] [--rate 30]\n");
  cl.option("--lcm-url", url)
      .option("--web-port", web_port)
      .option("--vmc-port", vmc_port)
      .option("--bvh-port", bvh_port)
      .option("--frames", frames)
      .option("--rate", rate);
  if (!cl.parse(argc, argv)) return 0;
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

  lo_server_thread osc = lo_server_thread_new(std::to_string(vmc_port).c_str(), nullptr);
  HULLPOSE_THROW_UNLESS(osc, "cannot listen for OSC on port " << vmc_port);
  lo_server_thread_add_method(osc, "/VMC/Ext/OK", nullptr, on_vmc_ok, &vmc);
  lo_server_thread_start(osc);

  asio::io_context io;
  namespace websocket = boost::beast::websocket;
  websocket::stream<tcp::socket> ws(io);
  ws.next_layer().connect(
      {asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(web_port)});
  ws.handshake("127.0.0.1", "/ws");
  std::thread ws_thread([&] {
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
  bvh_socket.connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(bvh_port)});
  bvh_socket.set_option(tcp::no_delay(true));
  std::thread bvh_thread([&] {
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
  for (size_t k = 0; k < n; ++k) {
    m->sample(static_cast<double>(k) / rate, f.joints);
    pacer.publish(static_cast<int64_t>(k), f);
    pacer.wait_next();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // stragglers
  stop = true;
  boost::system::error_code ec;
  ws.next_layer().shutdown(tcp::socket::shutdown_both, ec);
  bvh_socket.shutdown(tcp::socket::shutdown_both, ec);
  ws_thread.join();
  bvh_thread.join();
  lcm_thread.join();
  lo_server_thread_free(osc);

  for (auto [name, arrivals] :
       {std::pair<const char*, Arrivals*>{"web", &web}, {"vmc", &vmc}, {"bvh_tcp", &bvh}}) {
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
            {"name", std::string("consumers_added_latency_") + name + "_30hz"},
            {"median_ms", pct(added, 0.5)},
            {"p99_ms", pct(added, 0.99)},
            {"max_ms", added.empty() ? 0 : *std::max_element(added.begin(), added.end())},
            {"n", added.size()},
            {"lost", lost},
            {"rate_hz", rate},
            {"baseline", "arrival of SKELETON at a plain LCM subscriber in the same process"}}
            .dump()
            .c_str());
  }
  return 0;
}

int main(int argc, char** argv) {
  return hullpose::run_tool("consumers_bench", argc, argv, run);
}
