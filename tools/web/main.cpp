// hullpose-web: the live 3D view of the rig in a browser (SKELETON + STATUS, and HULL when the
// fusion host sends it, over LCM), or the playback of a recorded take (--play). Open the
// printed URL.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/skeleton_io/subscription.hpp"
#include "hullpose/web/web_server.hpp"

namespace {
const char* kUsage =
    "usage: hullpose-web [--rig FILE] [--lcm-url URL] [--rig-key FILE] [--rig-id ID] [--port 8080] "
    "[--bind 0.0.0.0] "
    "[--queue 8]\n"
    "         [--play TAKE (estimate .csv | lcm-logger log) [--fps 30] [--once]]\n"
    "         [--page DIR] [--three DIR] [--duration-s S] [--ready-file FILE]\n";

// The page: installed beside the program (PREFIX/share/hullpose/web for PREFIX/bin/hullpose-web,
// what the hullpose-consumers package holds), else this checkout's tools/web/page (a build tree
// runs in place). Found from the program's own path, so an unpacked or relocated tree works too.
std::filesystem::path default_page_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed =
        exe.parent_path().parent_path() / HULLPOSE_WEB_PAGE_INSTALL_DIR;
    if (std::filesystem::exists(installed / "index.html", ec)) return installed;
  }
  return HULLPOSE_WEB_PAGE_DIR;
}
}  // namespace

int run(int argc, const char* const* argv) {
  namespace sio = hullpose::skeleton_io;
  hullpose::web::WebOptions w;
  w.page_dir = default_page_dir();
  sio::SubscriptionOptions sub;
  std::string lcm_url, rig_key, rig_file, play, page = w.page_dir.string(),
                                                three = w.three_dir.string(), ready_file;
  long long queue = 8;
  double fps = 30, duration_s = 0;
  bool once = false;
  hullpose::cli::CommandLine cl(kUsage);
  cl.option("--rig", rig_file)
      .option("--lcm-url", lcm_url)
      .option("--rig-key", rig_key)
      .option("--rig-id", sub.rig_id)
      .option("--port", w.port)
      .option("--bind", w.bind)
      .option("--queue", queue)
      .option("--play", play)
      .option("--fps", fps)
      .flag("--once", once)
      .option("--page", page)
      .option("--three", three)
      .option("--duration-s", duration_s)
      .option("--ready-file", ready_file);
  if (!cl.parse(argc, argv)) return 0;
  HULLPOSE_THROW_UNLESS(w.port >= 0 && w.port <= 65535,
                        "--port must be in 0..65535, got " << w.port);
  HULLPOSE_THROW_UNLESS(queue >= 1 && queue <= 4096, "--queue must be in 1..4096, got " << queue);
  w.queue_capacity = static_cast<size_t>(queue);
  w.page_dir = page;
  w.three_dir = three;
  hullpose::Rig rig;
  if (!rig_file.empty()) rig = hullpose::load_rig(rig_file);
  hullpose::web::WebServer server(w, hullpose::web::rig_json(rig));
  const std::string url = "http://localhost:" + std::to_string(server.port()) + "/";
  std::fprintf(stderr, "hullpose-web: %s at %s\n",
               play.empty() ? "live view" : ("playback of " + play).c_str(), url.c_str());
  if (!ready_file.empty())
    std::ofstream(ready_file) << nlohmann::json{{"port", server.port()}, {"url", url}}.dump()
                              << "\n";

  hullpose::catch_stop_signals();
  const int64_t start = hullpose::monotonic_us();
  const int64_t end = duration_s > 0 ? start + static_cast<int64_t>(duration_s * 1e6) : INT64_MAX;
  if (!play.empty()) {
    const sio::Take take = sio::read_take(play, fps);
    HULLPOSE_THROW_UNLESS(!take.frames.empty(), play << ": no frames");
    const auto period = std::chrono::microseconds(static_cast<int64_t>(1e6 / take.fps));
    auto next = std::chrono::steady_clock::now();
    for (size_t i = 0; !hullpose::stop_requested() && hullpose::monotonic_us() < end; ++i) {
      if (i == take.frames.size()) {
        if (once) break;
        i = 0;
      }
      server.publish_skeleton(take.frames[i]);
      next += period;
      std::this_thread::sleep_until(next);  // the take's own clock
    }
  } else {
    const auto bus = hullpose::bus::open_bus(lcm_url, rig_key);
    sio::Subscription live(
        *bus, sub, [&](const sio::SkeletonFrame& f, int64_t) { server.publish_skeleton(f); },
        [&](const hullpose_msg::node_status_t& s) { server.publish_status(s); },
        [&](const hullpose::msg::CoarseHull& h) { server.publish_hull(h); });
    // LCM is read on the server's I/O thread: a pose reaches the browsers' sockets without a hop
    // between threads (make bench: tools/bench/peers/consumers_latency.sh).
    server.watch_readable(live.fd(), [&] { live.poll(0); });
    while (!hullpose::stop_requested() && hullpose::monotonic_us() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    server.stop();  // before `live` goes: its socket is watched on the server's thread
    for (const auto& [name, value] : live.counters().snapshot())
      std::fprintf(stderr, "hullpose-web: %s=%lld\n", name.c_str(), static_cast<long long>(value));
  }
  std::fprintf(stderr, "hullpose-web: %s\n", server.stats_json().c_str());
  return 0;
}

int main(int argc, char** argv) {
  return hullpose::run_tool("hullpose-web", argc, argv, run);
}
