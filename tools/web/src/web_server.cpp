#include "hullpose/web/web_server.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hullpose/common/check.hpp"
#include "hullpose/skeleton_io/asio.hpp"

namespace hullpose::web {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using asio::ip::tcp;
using nlohmann::json;

namespace {

json vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
double tenth(double v) {
  return std::round(v * 10) / 10;
}

}  // namespace

std::string rig_json(const Rig& rig) {
  json cams = json::array();
  for (const CameraModel& c : rig.cameras) {
    cams.push_back({{"id", c.id},
                    {"centre", vec(c.centre())},
                    {"right", vec(c.R.row(0).transpose())},
                    {"down", vec(c.R.row(1).transpose())},
                    {"forward", vec(c.R.row(2).transpose())},
                    {"half_width", c.width / (2 * c.fx)},
                    {"half_height", c.height / (2 * c.fy)}});
  }
  return json{{"rig_id", rig.rig_id},
              {"volume", {{"min", vec(rig.volume.min_mm)}, {"max", vec(rig.volume.max_mm)}}},
              {"cameras", cams}}
      .dump();
}

std::string skeleton_json(const skeleton_io::SkeletonFrame& f) {
  json joints = json::array(), confidence = json::array();
  for (size_t j = 0; j < kNumJoints; ++j) {
    joints.push_back({tenth(f.joints[j].x()), tenth(f.joints[j].y()), tenth(f.joints[j].z())});
    confidence.push_back(std::round(f.confidence[j] * 100) / 100);
  }
  return json{{"type", "skeleton"},
              {"seq", f.seq},
              {"utime", f.utime},
              {"valid", f.valid},
              {"reason", f.reason},
              {"joints", joints},
              {"confidence", confidence},
              {"cameras", f.num_cameras_used},
              {"latency_ms", f.published_us / 1000.0}}
      .dump();
}

std::string status_json(const hullpose_msg::node_status_t& s) {
  json stages = json::object(), counters = json::object();
  for (size_t i = 0; i < s.stage_name.size() && i < s.stage_ms.size(); ++i)
    stages[s.stage_name[i]] = s.stage_ms[i];
  for (size_t i = 0; i < s.counter_name.size() && i < s.counter_value.size(); ++i)
    counters[s.counter_name[i]] = s.counter_value[i];
  // Names and messages come from the network: invalid UTF-8 is replaced, not thrown.
  return json{{"type", "status"},
              {"utime", s.utime},
              {"rig_id", s.rig_id},
              {"role", s.role},
              {"node_id", s.node_id},
              {"hostname", s.hostname},
              {"state", s.state},
              {"message", s.message},
              {"fps", s.fps},
              {"frames_total", s.frames_total},
              {"last_trigger_seq", s.last_trigger_seq},
              {"stages", stages},
              {"counters", counters}}
      .dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string hull_json(const msg::CoarseHull& h) {
  const auto [nx, ny, nz] = h.dims;
  const auto at = [&](int x, int y, int z) {
    return x >= 0 && y >= 0 && z >= 0 && x < nx && y < ny && z < nz && h.occupied(x, y, z);
  };
  json voxels = json::array();
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        if (at(x, y, z) && !(at(x - 1, y, z) && at(x + 1, y, z) && at(x, y - 1, z) &&
                             at(x, y + 1, z) && at(x, y, z - 1) && at(x, y, z + 1))) {
          voxels.push_back(x);
          voxels.push_back(y);
          voxels.push_back(z);
        }
  return json{{"type", "hull"},
              {"seq", h.trigger_seq},
              {"utime", h.utime},
              {"dims", {nx, ny, nz}},
              {"origin", {h.origin_mm[0], h.origin_mm[1], h.origin_mm[2]}},
              {"voxel_mm", h.voxel_mm},
              {"carved_voxel_mm", h.carved_voxel_mm},
              {"occupied", h.num_occupied},
              {"voxels", voxels}}
      .dump();
}

class WebServer::WsSession final : public skeleton_io::OutboundSession {
 public:
  WsSession(tcp::socket socket, WebServer& server)
      : OutboundSession(server.fanout_.stats(), server.capacity_),
        ws_(std::move(socket)),
        server_(server) {
    boost::system::error_code ec;
    ws_.next_layer().set_option(tcp::no_delay(true),
                                ec);  // a pose is small and wanted now: no Nagle
  }

  void start(http::request<http::string_body> request) {
    request_ = std::move(request);
    // Pings an idle browser and closes one that stops answering (a vanished laptop).
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.text(true);
    ws_.async_accept(request_, [self = shared_from_this(), this](beast::error_code ec) {
      if (ec) return;
      server_.fanout_.add(self);
      for (const auto& [key, message] : server_.last_status_) deliver(message);
      read();
    });
  }

 private:
  // The page sends nothing; reading notices it leaving.
  void read() {
    ws_.async_read(in_, [self = shared_from_this(), this](beast::error_code ec, size_t) {
      if (ec) return close();
      in_.clear();
      read();
    });
  }
  void async_send(const std::string& m, std::function<void(bool)> done) override {
    ws_.async_write(asio::buffer(m),
                    [done = std::move(done)](beast::error_code ec, size_t) { done(!ec); });
  }
  void do_close() override {
    beast::error_code ec;
    beast::get_lowest_layer(ws_).close(ec);
  }

  websocket::stream<tcp::socket> ws_;
  WebServer& server_;
  http::request<http::string_body> request_;
  beast::flat_buffer in_;
};

class WebServer::HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, WebServer& server)
      : stream_(std::move(socket)), server_(server) {}
  void read() {
    request_ = {};
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(
        stream_, buffer_, request_,
        [self = shared_from_this()](beast::error_code ec, size_t) { self->on_read(ec); });
  }

 private:
  void on_read(beast::error_code ec) {
    if (ec) return close();
    if (websocket::is_upgrade(request_)) {
      if (request_.target() != "/ws") return close();
      stream_.expires_never();
      std::make_shared<WsSession>(stream_.release_socket(), server_)->start(std::move(request_));
      return;
    }
    auto res = std::make_shared<http::response<http::string_body>>();
    res->version(request_.version());
    res->keep_alive(request_.keep_alive());
    res->set(http::field::server, "hullpose-web");
    res->set(http::field::cache_control, "no-store");
    std::string target(request_.target());
    target = target.substr(0, target.find('?'));
    if (request_.method() != http::verb::get && request_.method() != http::verb::head) {
      res->result(http::status::method_not_allowed);
      res->body() = "GET only\n";
    } else if (target == "/stats.json") {
      res->result(http::status::ok);
      res->set(http::field::content_type, "application/json");
      res->body() = server_.stats_json();
    } else if (auto it = server_.assets_.find(target); it != server_.assets_.end()) {
      res->result(http::status::ok);
      res->set(http::field::content_type, it->second.mime);
      res->body() = it->second.body;
    } else {
      res->result(http::status::not_found);
      res->set(http::field::content_type, "text/plain");
      res->body() = "not found: " + target + "\n";
    }
    if (request_.method() == http::verb::head) res->body().clear();
    res->prepare_payload();
    http::async_write(stream_, *res,
                      [self = shared_from_this(), res](beast::error_code wec, size_t) {
                        if (wec || !res->keep_alive()) return self->close();
                        self->read();
                      });
  }
  void close() {
    beast::error_code ec;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
  }

  beast::tcp_stream stream_;
  WebServer& server_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
};

void WebServer::load_assets(const WebOptions& o) {
  const auto load = [&](const std::string& url, const std::filesystem::path& file,
                        const std::string& mime) {
    std::ifstream in(file, std::ios::binary);
    HULLPOSE_THROW_UNLESS(in.good(), file.string() << ": cannot read (needed for " << url << ")");
    std::ostringstream body;
    body << in.rdbuf();
    assets_[url] = {body.str(), mime};
  };
  load("/", o.page_dir / "index.html", "text/html; charset=utf-8");
  load("/app.js", o.page_dir / "app.js", "text/javascript");
  load("/three/three.min.js", o.three_dir / "three.min.js", "text/javascript");
  load("/three/OrbitControls.js", o.three_dir / "examples/js/controls/OrbitControls.js",
       "text/javascript");
}

WebServer::WebServer(const WebOptions& o, std::string rig)
    : capacity_(o.queue_capacity), acceptor_(io_), fanout_(io_) {
  load_assets(o);
  assets_["/rig.json"] = {std::move(rig), "application/json"};
  port_ = skeleton_io::listen_on(acceptor_, o.bind, o.port, "--port");
  accept();
  thread_ = std::thread([this] { io_.run(); });
}

WebServer::~WebServer() {
  stop();
}

void WebServer::stop() {
  skeleton_io::stop_service(io_, acceptor_, fanout_, thread_);
}

void WebServer::accept() {
  acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec) return;
    std::make_shared<HttpSession>(std::move(socket), *this)->read();
    accept();
  });
}

void WebServer::publish_skeleton(const skeleton_io::SkeletonFrame& f) {
  fanout_.publish(std::make_shared<const std::string>(skeleton_json(f)));
}

void WebServer::publish_status(const hullpose_msg::node_status_t& s) {
  auto m = std::make_shared<const std::string>(status_json(s));
  std::string key = s.role + "/" + std::to_string(s.node_id);
  asio::post(io_, [this, key = std::move(key), m] {
    if (last_status_.size() < 1024 || last_status_.count(key))
      last_status_[key] = m;  // bounded: hostile senders
  });
  fanout_.publish(std::move(m));
}

void WebServer::publish_hull(const msg::CoarseHull& h) {
  ++hulls_;
  fanout_.publish(std::make_shared<const std::string>(hull_json(h)));
}

std::string WebServer::stats_json() const {
  const auto& s = fanout_.stats();
  return json{{"sessions", s.sessions.load()},   {"accepted", s.accepted.load()},
              {"published", s.published.load()}, {"sent", s.sent.load()},
              {"dropped", s.dropped.load()},     {"closed", s.closed.load()},
              {"hulls", hulls_.load()}}
      .dump();
}

}  // namespace hullpose::web
