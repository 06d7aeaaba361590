// hullpose-stream: SKELETON to animation tools. Outputs chosen on the command line, any together:
// VMC over OSC (Unity / VTuber tools), BVH motion lines over TCP (a server) and/or UDP.
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/skeleton_io/subscription.hpp"
#include "hullpose/stream/bridges.hpp"

namespace {
const char* kUsage =
    "usage: hullpose-stream [--lcm-url URL] [--rig-key FILE] [--channel SKELETON] [--rig-id ID]\n"
    "         [--vmc HOST:PORT] [--bvh-tcp PORT [--bvh-bind 0.0.0.0]] [--bvh-udp HOST:PORT] "
    "[--bvh-format axis|plain]\n"
    "         [--queue 8] [--duration-s S] [--ready-file FILE] [--stats FILE]\n";

struct Options {
  hullpose::skeleton_io::SubscriptionOptions sub;
  std::string lcm_url, rig_key, vmc, bvh_udp, bvh_bind = "0.0.0.0", bvh_format = "axis", ready_file,
                                              stats;
  int bvh_tcp = -1;
  long long queue = 8;
  double duration_s = 0;
};
}  // namespace

int run(int argc, const char* const* argv) {
  namespace sio = hullpose::skeleton_io;
  namespace hs = hullpose::stream;
  Options o;
  o.sub.status_channel.clear();
  hullpose::cli::CommandLine cl(kUsage);
  cl.option("--lcm-url", o.lcm_url)
      .option("--rig-key", o.rig_key)
      .option("--channel", o.sub.skeleton_channel)
      .option("--rig-id", o.sub.rig_id)
      .option("--vmc", o.vmc)
      .option("--bvh-tcp", o.bvh_tcp)
      .option("--bvh-bind", o.bvh_bind)
      .option("--bvh-udp", o.bvh_udp)
      .option("--bvh-format", o.bvh_format)
      .option("--queue", o.queue)
      .option("--duration-s", o.duration_s)
      .option("--ready-file", o.ready_file)
      .option("--stats", o.stats);
  if (!cl.parse(argc, argv)) return 0;
  HULLPOSE_THROW_UNLESS(!o.vmc.empty() || o.bvh_tcp >= 0 || !o.bvh_udp.empty(),
                        "no output: give --vmc, --bvh-tcp and/or --bvh-udp");
  HULLPOSE_THROW_UNLESS(o.bvh_tcp <= 65535,
                        "--bvh-tcp: port must be in 0..65535, got " << o.bvh_tcp);
  HULLPOSE_THROW_UNLESS(o.queue >= 1 && o.queue <= 4096,
                        "--queue must be in 1..4096, got " << o.queue);
  const hs::BvhLineFormat format = hs::parse_line_format(o.bvh_format);

  std::unique_ptr<hs::VmcOutput> vmc;
  std::unique_ptr<hs::BvhTcpServer> tcp;
  std::unique_ptr<hs::BvhUdpOutput> udp;
  if (!o.vmc.empty()) {
    const auto [host, port] = hs::parse_endpoint("--vmc", o.vmc);
    vmc = std::make_unique<hs::VmcOutput>(host, port);
  }
  if (o.bvh_tcp >= 0)
    tcp = std::make_unique<hs::BvhTcpServer>(o.bvh_bind, o.bvh_tcp, format,
                                             static_cast<size_t>(o.queue));
  if (!o.bvh_udp.empty()) {
    const auto [host, port] = hs::parse_endpoint("--bvh-udp", o.bvh_udp);
    udp = std::make_unique<hs::BvhUdpOutput>(host, port, format);
  }

  hs::LiveSkeleton skeleton;
  std::vector<double> channels;
  int64_t frames = 0, invalid = 0;
  const int64_t start = hullpose::monotonic_us();
  const auto bus = hullpose::bus::open_bus(o.lcm_url, o.rig_key);
  sio::Subscription sub(*bus, o.sub, [&](const sio::SkeletonFrame& f, int64_t) {
    ++frames;
    if (!f.valid) ++invalid;
    const bool ready = skeleton.update(f);
    if (vmc) vmc->send(f, skeleton, static_cast<double>(hullpose::monotonic_us() - start) * 1e-6);
    if (!ready || !f.valid) return;  // BVH receivers hold the last pose through invalid frames
    skeleton.bvh().solve(f.joints, channels);
    if (tcp) tcp->send(f, skeleton, channels);
    if (udp) udp->send(channels);
  });
  if (!o.ready_file.empty()) {
    std::ofstream ready(o.ready_file);
    ready << nlohmann::json{{"bvh_tcp_port", tcp ? tcp->port() : -1}}.dump() << "\n";
  }
  hullpose::catch_stop_signals();
  const int64_t end =
      o.duration_s > 0 ? start + static_cast<int64_t>(o.duration_s * 1e6) : INT64_MAX;
  if (tcp) {
    // With a TCP server, LCM is read on its I/O thread (every output is sent from there):
    // no hop between threads on the way to the clients' sockets.
    tcp->watch_readable(sub.fd(), [&] { sub.poll(0); });
    while (!hullpose::stop_requested() && hullpose::monotonic_us() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  } else {
    while (!hullpose::stop_requested() && hullpose::monotonic_us() < end) sub.poll(100);
  }

  nlohmann::json stats = {{"frames", frames}, {"invalid", invalid}};
  for (const auto& [name, value] : sub.counters().snapshot()) stats[name] = value;
  if (vmc) stats["vmc"] = {{"sent", vmc->sent()}, {"failed", vmc->failed()}};
  if (udp) stats["bvh_udp"] = {{"sent", udp->sent()}, {"failed", udp->failed()}};
  if (tcp) {
    const auto& s = tcp->stats();
    stats["bvh_tcp"] = {{"accepted", s.accepted.load()},
                        {"published", s.published.load()},
                        {"sent", s.sent.load()},
                        {"dropped", s.dropped.load()},
                        {"closed", s.closed.load()}};
  }
  if (!o.stats.empty()) std::ofstream(o.stats) << stats.dump() << "\n";
  std::fprintf(stderr, "hullpose-stream: %s\n", stats.dump().c_str());
  return 0;
}

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-stream", argc, argv, run);
}
