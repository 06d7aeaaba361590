#pragma once
// hullpose-web's server: HTTP for the page and its assets (Boost.Beast), one WebSocket (/ws) per
// browser carrying skeleton, status and (when the fusion host sends them, --hull-rate) coarse hull
// messages as JSON text. Every browser has its own
// drop-oldest queue (skeleton_io/fanout.hpp): a slow or vanished browser loses old poses,
// counted, and never slows the caller of publish_*(). Runs its own I/O thread.
//
// URLs: /            the page (page/index.html)       /app.js    its script
//       /three/...   three.js from Debian's libjs-three (three.min.js, OrbitControls.js)
//       /rig.json    the rig: capture volume and each camera's centre and axes (mm, rig frame)
//       /stats.json  counters (sessions, sent, dropped, ...)         /ws  the WebSocket
#include <atomic>
#include <filesystem>
#include <hullpose_msg/node_status_t.hpp>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include "hullpose/common/rig.hpp"
#include "hullpose/msg/hull.hpp"
#include "hullpose/skeleton_io/asio.hpp"
#include "hullpose/skeleton_io/fanout.hpp"
#include "hullpose/skeleton_io/take.hpp"

namespace hullpose::web {

struct WebOptions {
  std::string bind = "0.0.0.0";
  int port = 8080;                 // 0: any free port (see WebServer::port())
  std::filesystem::path page_dir;  // index.html, app.js
  std::filesystem::path three_dir = "/usr/share/javascript/three";
  size_t queue_capacity = 8;  // messages per browser
};

// The page's view of the rig (JSON text): volume, cameras (id, centre, right/down/forward axes,
// fov).
std::string rig_json(const Rig& rig);
// One skeleton / status as the page reads them.
std::string skeleton_json(const skeleton_io::SkeletonFrame& f);
std::string status_json(const hullpose_msg::node_status_t& s);
// The hull as the page draws it: grid geometry and the surface voxels only (an occupied voxel
// with an empty or outside 6-neighbour), as flat [x, y, z, ...] — the inside is never seen.
std::string hull_json(const msg::CoarseHull& h);

class WebServer {
 public:
  // Throws hullpose::Error if the page or three.js files are missing or the port cannot be bound.
  WebServer(const WebOptions& options, std::string rig_json);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  int port() const { return port_; }
  // Closes every session and joins the I/O thread (idempotent; the destructor calls it). Call it
  // before destroying what a watch_readable callback uses.
  void stop();
  // Runs on_readable on the server's I/O thread when fd has data (the LCM socket: then a
  // skeleton goes from LCM to every browser's socket on one thread). Call once, before traffic.
  void watch_readable(int fd, std::function<void()> on_readable) {
    fanout_.watch_readable(fd, std::move(on_readable));
  }
  // Any thread; never blocks on a browser.
  void publish_skeleton(const skeleton_io::SkeletonFrame& f);
  void publish_status(const hullpose_msg::node_status_t& s);
  void publish_hull(const msg::CoarseHull& h);
  const skeleton_io::FanoutStats& stats() const { return fanout_.stats(); }
  std::string stats_json() const;

 private:
  class HttpSession;
  class WsSession;
  struct Asset {
    std::string body, mime;
  };
  void accept();
  void load_assets(const WebOptions& o);

  size_t capacity_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  skeleton_io::Fanout fanout_;
  std::map<std::string, Asset> assets_;  // immutable after construction
  // Latest status of each node (key role/node_id), replayed to a browser when it connects; I/O
  // thread only.
  std::map<std::string, skeleton_io::Message> last_status_;
  int port_ = 0;
  std::atomic<int64_t> hulls_{0};  // hulls published to the browsers
  std::thread thread_;
};

}  // namespace hullpose::web
