#include "hullpose/stream/bridges.hpp"

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"

namespace hullpose::stream {

namespace asio = boost::asio;
using asio::ip::tcp;
using asio::ip::udp;

std::pair<std::string, int> parse_endpoint(const std::string& what, const std::string& text) {
  const auto colon = text.rfind(':');
  HULLPOSE_THROW_UNLESS(colon != std::string::npos && colon > 0,
                        what << ": expected HOST:PORT, got '" << text << "'");
  const long long port = cli::parse_integer(what, text.substr(colon + 1));
  HULLPOSE_THROW_UNLESS(port >= 1 && port <= 65535,
                        what << ": port must be in 1..65535, got " << port);
  return {text.substr(0, colon), static_cast<int>(port)};
}

bool LiveSkeleton::update(const SkeletonFrame& f) {
  if (f.valid && (!bvh_ || f.model_version > model_)) {
    bvh_.emplace(skeleton_io::bone_lengths(f.joints));
    model_ = f.model_version;
    ++generation_;
  }
  return bvh_.has_value();
}

// ---- VMC over OSC ----------------------------------------------------------------------------

VmcOutput::VmcOutput(const std::string& host, int port)
    : address_(lo_address_new(host.c_str(), std::to_string(port).c_str())) {
  HULLPOSE_THROW_UNLESS(address_ != nullptr,
                        "--vmc: cannot make an OSC address of " << host << ":" << port);
}

VmcOutput::~VmcOutput() {
  lo_address_free(address_);
}

void VmcOutput::send(const SkeletonFrame& f, const LiveSkeleton& skeleton, double time_s) {
  // liblo builds each message on the heap; at 30 Hz x 22 messages that is noise next to the send.
  lo_bundle bundle = lo_bundle_new(LO_TT_IMMEDIATE);
  const auto add = [&](const char* path, lo_message m) { lo_bundle_add_message(bundle, path, m); };
  const auto pose = [](lo_message m, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
    for (double v : {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()})
      lo_message_add_float(m, static_cast<float>(v));
  };
  const bool tracking = f.valid && skeleton.ready();
  lo_message ok = lo_message_new();
  lo_message_add_int32(ok, 1);                 // loaded
  lo_message_add_int32(ok, 3);                 // calibration state: calibrated
  lo_message_add_int32(ok, 0);                 // calibration mode: normal
  lo_message_add_int32(ok, tracking ? 1 : 0);  // tracking status
  add("/VMC/Ext/OK", ok);
  lo_message t = lo_message_new();
  lo_message_add_float(t, static_cast<float>(time_s));
  add("/VMC/Ext/T", t);
  if (tracking) {
    if (map_generation_ != skeleton.generation()) {
      map_.emplace(skeleton.bvh());
      map_generation_ = skeleton.generation();
    }
    map_->pose(f.joints, bones_);
    lo_message root = lo_message_new();
    lo_message_add_string(root, "root");
    pose(root, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
    add("/VMC/Ext/Root/Pos", root);
    for (const skeleton_io::HumanoidBone& b : bones_) {
      lo_message m = lo_message_new();
      lo_message_add_string(m, std::string(b.name).c_str());
      pose(m, b.position, b.rotation);
      add("/VMC/Ext/Bone/Pos", m);
    }
  }
  // UDP: a receiver that is slow or gone costs nothing here (the kernel drops).
  if (lo_send_bundle(address_, bundle) < 0)
    ++failed_;
  else
    ++sent_;
  lo_bundle_free_recursive(bundle);
}

// ---- BVH lines -------------------------------------------------------------------------------

BvhLineFormat parse_line_format(const std::string& text) {
  if (text == "plain") return BvhLineFormat::Plain;
  if (text == "axis") return BvhLineFormat::Axis;
  HULLPOSE_THROW("--bvh-format must be plain or axis, got '" << text << "'");
}

void format_bvh_line(BvhLineFormat format, const std::vector<double>& channels,
                     std::string& scratch, std::string& out) {
  skeleton_io::BvhSkeleton::format_line(channels, scratch);
  out.clear();
  if (format == BvhLineFormat::Plain) {
    out += scratch;
    return;
  }
  out += "0 hullpose ";
  out.append(scratch, 0, scratch.size() - 1);  // without the newline
  out += " ||\n";
}

class BvhTcpServer::Session final : public skeleton_io::OutboundSession {
 public:
  Session(tcp::socket socket, skeleton_io::FanoutStats& stats, size_t capacity)
      : OutboundSession(stats, capacity), socket_(std::move(socket)) {
    boost::system::error_code ec;
    socket_.set_option(tcp::no_delay(true), ec);
  }
  // Reads only to notice the client leaving (it has nothing to say).
  void watch() {
    socket_.async_read_some(asio::buffer(sink_), [self = shared_from_this(), this](
                                                     boost::system::error_code ec, size_t) {
      if (ec) return close();
      watch();
    });
  }

 private:
  void async_send(const std::string& m, std::function<void(bool)> done) override {
    asio::async_write(
        socket_, asio::buffer(m),
        [done = std::move(done)](boost::system::error_code ec, size_t) { done(!ec); });
  }
  void do_close() override {
    boost::system::error_code ec;
    socket_.close(ec);
  }
  tcp::socket socket_;
  std::array<char, 256> sink_{};
};

BvhTcpServer::BvhTcpServer(const std::string& bind, int port, BvhLineFormat format, size_t capacity)
    : format_(format), capacity_(capacity), acceptor_(io_), fanout_(io_) {
  port_ = skeleton_io::listen_on(acceptor_, bind, port, "--bvh-tcp");
  accept();
  thread_ = std::thread([this] { io_.run(); });
}

BvhTcpServer::~BvhTcpServer() {
  stop();
}

void BvhTcpServer::stop() {
  skeleton_io::stop_service(io_, acceptor_, fanout_, thread_);
}

void BvhTcpServer::accept() {
  acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec) return;  // acceptor closed
    auto session = std::make_shared<Session>(std::move(socket), fanout_.stats(), capacity_);
    fanout_.add(session);
    session->watch();
    if (header_) session->deliver(header_);
    accept();
  });
}

void BvhTcpServer::send(const SkeletonFrame& f, const LiveSkeleton& skeleton,
                        const std::vector<double>& channels) {
  if (!f.valid || !skeleton.ready()) return;
  // A new skeleton (a held body model arrived): clients that connect from now on get its
  // hierarchy; those here already keep theirs (a plain BVH stream has one) and the rotations.
  if (format_ == BvhLineFormat::Plain && header_generation_ != skeleton.generation()) {
    const bool first = header_generation_ == 0;
    std::ostringstream hierarchy;
    skeleton.bvh().write_header(hierarchy, 0, 0);
    auto h = std::make_shared<const std::string>(hierarchy.str());
    asio::post(io_, [this, h] { header_ = h; });  // for clients that connect later
    if (first) fanout_.publish(h);                // and for those here now
    header_generation_ = skeleton.generation();
  }
  format_bvh_line(format_, channels, scratch_, line_);
  fanout_.publish(std::make_shared<const std::string>(line_));
}

BvhUdpOutput::BvhUdpOutput(const std::string& host, int port, BvhLineFormat format)
    : format_(format), socket_(io_) {
  boost::system::error_code ec;
  udp::resolver resolver(io_);
  const auto results = resolver.resolve(udp::v4(), host, std::to_string(port), ec);
  HULLPOSE_THROW_UNLESS(!ec && !results.empty(),
                        "--bvh-udp: cannot resolve " << host << ":" << port);
  to_ = *results.begin();
  socket_.open(udp::v4(), ec);
  HULLPOSE_THROW_UNLESS(!ec, "--bvh-udp: cannot open a UDP socket: " << ec.message());
  socket_.non_blocking(true, ec);  // a full send buffer is a counted drop, not a wait
}

void BvhUdpOutput::send(const std::vector<double>& channels) {
  format_bvh_line(format_, channels, scratch_, line_);
  boost::system::error_code ec;
  socket_.send_to(asio::buffer(line_), to_, 0, ec);
  if (ec)
    ++failed_;
  else
    ++sent_;
}

}  // namespace hullpose::stream
