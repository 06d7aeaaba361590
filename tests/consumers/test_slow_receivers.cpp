// A receiver that stops reading (a frozen browser, a stalled animation tool) or vanishes never
// slows the producer or grows memory: its messages are dropped oldest first and counted, while a
// receiver that keeps up gets the newest message. Real sockets on loopback, no LCM.
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "hullpose/skeleton_io/asio.hpp"
#include "hullpose/stream/bridges.hpp"
#include "hullpose/synth/motion.hpp"
#include "hullpose/web/web_server.hpp"

using namespace hullpose;
namespace asio = boost::asio;
using asio::ip::tcp;

namespace {

// A client that connects and then never reads, with a small receive buffer so it fills soon.
tcp::socket stalled_client(asio::io_context& io, int port) {
  tcp::socket s(io);
  s.open(tcp::v4());
  s.set_option(asio::socket_base::receive_buffer_size(4096));
  s.connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
  return s;
}

template <typename Stats, typename Cond>
void publish_until(Stats& stats, Cond done, const std::function<void(int)>& publish) {
  // Bounded: a producer that blocked would never get here; a queue that never dropped fails below.
  for (int i = 0; i < 200'000 && !done(); ++i) publish(i);
  (void)stats;
}

}  // namespace

TEST_CASE(
    "BVH over TCP: a stalled client loses old lines, a reading one gets the newest, the producer "
    "never waits") {
  stream::BvhTcpServer server("127.0.0.1", 0, stream::BvhLineFormat::Axis, 4);
  asio::io_context io;
  tcp::socket stalled = stalled_client(io, server.port());
  tcp::socket reader(io);
  reader.connect({asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(server.port())});
  while (server.stats().sessions.load() < 2) std::this_thread::yield();

  const auto m = synth::make_builtin_motion("walk", {});
  skeleton_io::SkeletonFrame f;
  f.valid = true;
  m->sample(0, f.joints);
  stream::LiveSkeleton skeleton;
  REQUIRE(skeleton.update(f));
  std::vector<double> channels;
  skeleton.bvh().solve(f.joints, channels);

  std::atomic<bool> stop{false};
  std::atomic<int64_t> lines{0};
  std::string last;
  std::thread read_thread([&] {
    asio::streambuf buf;
    boost::system::error_code ec;
    while (!stop) {
      asio::read_until(reader, buf, '\n', ec);
      if (ec) break;
      std::istream in(&buf);
      std::getline(in, last);
      ++lines;
    }
  });
  int published = 0;
  publish_until(
      server.stats(), [&] { return server.stats().dropped.load() > 1000; },
      [&](int i) {
        channels[0] = i;  // the root x carries the index
        server.send(f, skeleton, channels);
        published = i + 1;
      });
  CHECK(server.stats().dropped.load() > 1000);
  // The last line published reaches the reading client (drop-oldest keeps the newest).
  channels[0] = 1e6;
  server.send(f, skeleton, channels);
  while (last.rfind("0 hullpose 1000000.000000 ", 0) != 0) std::this_thread::yield();
  CHECK(server.stats().published.load() == published + 1);
  // Sent + dropped + still queued = published x clients: the stalled client holds at most 4 + 1.
  const int64_t unaccounted =
      2 * (published + 1) - server.stats().sent.load() - server.stats().dropped.load();
  CHECK(unaccounted >= 0);
  CHECK(unaccounted <= 2 * (4 + 1));
  stop = true;
  reader.shutdown(tcp::socket::shutdown_both);
  read_thread.join();
  // A client that vanishes is closed and forgotten.
  stalled.close();
  for (int i = 0; i < 100'000 && server.stats().sessions.load() > 1; ++i) {
    server.send(f, skeleton, channels);
    if (i % 100 == 0) std::this_thread::yield();
  }
  CHECK(server.stats().sessions.load() <= 1);
}

TEST_CASE(
    "web: a browser that stops reading loses old skeletons (counted) and the server stays "
    "bounded") {
  web::WebOptions o;
  o.bind = "127.0.0.1";
  o.port = 0;
  o.page_dir = HULLPOSE_SOURCE_DIR "/tools/web/page";
  o.queue_capacity = 4;
  web::WebServer server(o, "{}");
  asio::io_context io;
  namespace ws = boost::beast::websocket;
  ws::stream<tcp::socket> client(stalled_client(io, server.port()));
  client.handshake("127.0.0.1", "/ws");  // then never reads
  while (server.stats().sessions.load() < 1) std::this_thread::yield();
  skeleton_io::SkeletonFrame f;
  f.valid = true;
  for (int i = 0; i < 200'000 && server.stats().dropped.load() < 1000; ++i) {
    f.seq = i;
    server.publish_skeleton(f);
  }
  CHECK(server.stats().dropped.load() >= 1000);
  CHECK(server.stats().sent.load() < server.stats().published.load());
  CHECK(server.stats_json().find("\"dropped\":") != std::string::npos);
}

TEST_CASE("web: JSON of hostile status text does not throw") {
  hullpose_msg::node_status_t s{};
  s.role = "camera_node";
  s.message = std::string("bad \xff\xfe utf-8");
  s.stage_name = {"x\xc3"};
  s.stage_ms = {1.f};
  const std::string j = web::status_json(s);
  CHECK(j.find("camera_node") != std::string::npos);
}

TEST_CASE("live BVH skeleton: fixed by the first valid frame, again by each newer held model") {
  const auto m = synth::make_builtin_motion("walk", {});
  skeleton_io::SkeletonFrame f;
  m->sample(0, f.joints);
  stream::LiveSkeleton s;
  CHECK_FALSE(s.update(f));  // invalid: nothing fixed yet
  f.valid = true;
  REQUIRE(s.update(f));
  CHECK(s.generation() == 1);
  const auto provisional = skeleton_io::bone_lengths(f.joints);
  for (auto& j : f.joints) j *= 0.9;  // the held model's shorter bones
  f.model_version = 1;
  s.update(f);
  CHECK(s.generation() == 2);
  const auto held = skeleton_io::bone_lengths(f.joints);
  CHECK(held[5] == Approx(0.9 * provisional[5]));
  for (auto& j : f.joints) j *= 1.1;  // the same model again: already fixed
  s.update(f);
  f.model_version = 0;
  s.update(f);
  CHECK(s.generation() == 2);
  const auto& lsho = s.bvh().nodes()[static_cast<size_t>(s.bvh().find("LSho"))];
  CHECK(lsho.offset.norm() * 10 == Approx(held[3]));
}
