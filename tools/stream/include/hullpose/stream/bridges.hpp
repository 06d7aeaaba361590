#pragma once
// hullpose-stream's outputs, each a thin adapter over SKELETON: it turns a frame into its wire
// form and hands it on without waiting for any receiver.
//   VmcOutput      VMC protocol (OSC over UDP, liblo): one bundle per frame, Unity humanoid bones
//   BvhTcpServer   BVH motion lines to every connected TCP client (drop-oldest queue per client)
//   BvhUdpOutput   BVH motion lines as UDP datagrams to one receiver
// The BVH skeleton (bone lengths) is taken from the first valid frame and kept for the session,
// so every line a client sees belongs to one hierarchy.
#include <lo/lo.h>

#include <array>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hullpose/skeleton_io/asio.hpp"
#include "hullpose/skeleton_io/bvh.hpp"
#include "hullpose/skeleton_io/fanout.hpp"
#include "hullpose/skeleton_io/humanoid.hpp"

namespace hullpose::stream {

using skeleton_io::SkeletonFrame;

// "host:port" -> parts; throws hullpose::Error naming `what` (the option).
std::pair<std::string, int> parse_endpoint(const std::string& what, const std::string& text);

// The session's BVH skeleton: fixed by the first valid frame, and fixed again by the first frame
// of each newer held body model (model_version; its lengths then hold for good), so receivers
// end up with the subject's locked lengths, not a provisional frame's.
class LiveSkeleton {
 public:
  // False until a valid frame has fixed the skeleton.
  bool update(const SkeletonFrame& f);
  const skeleton_io::BvhSkeleton& bvh() const { return *bvh_; }
  bool ready() const { return bvh_.has_value(); }
  // Changes whenever the skeleton is fixed anew (outputs rebuild what they derived from it).
  int generation() const { return generation_; }

 private:
  std::optional<skeleton_io::BvhSkeleton> bvh_;
  int32_t model_ = 0;
  int generation_ = 0;
};

class VmcOutput {
 public:
  VmcOutput(const std::string& host, int port);
  ~VmcOutput();
  VmcOutput(const VmcOutput&) = delete;
  VmcOutput& operator=(const VmcOutput&) = delete;
  // An invalid frame sends /VMC/Ext/OK with tracking lost and no bones (receivers hold the pose).
  void send(const SkeletonFrame& f, const LiveSkeleton& skeleton, double time_s);
  int64_t sent() const { return sent_; }
  int64_t failed() const { return failed_; }

 private:
  lo_address address_;
  std::optional<skeleton_io::HumanoidMap> map_;
  int map_generation_ = 0;  // LiveSkeleton::generation the map was made for (0: none)
  std::array<skeleton_io::HumanoidBone, skeleton_io::kNumHumanoidBones> bones_{};
  int64_t sent_ = 0, failed_ = 0;
};

enum class BvhLineFormat {
  Plain,
  Axis
};  // plain motion line | "0 hullpose <values> ||" (Axis Neuron)
BvhLineFormat parse_line_format(const std::string& text);
// The wire text of one frame (no allocation once `out` has grown).
void format_bvh_line(BvhLineFormat format, const std::vector<double>& channels,
                     std::string& scratch, std::string& out);

class BvhTcpServer {
 public:
  // Listens on 127.0.0.1/0.0.0.0 `port` (0: any free port, see port()); runs its own I/O thread.
  // Plain format: a client first gets the HIERARCHY (once the skeleton is known), then lines.
  BvhTcpServer(const std::string& bind, int port, BvhLineFormat format, size_t queue_capacity);
  ~BvhTcpServer();
  int port() const { return port_; }
  // Closes every session and joins the I/O thread (idempotent; the destructor calls it). Call it
  // before destroying what a watch_readable callback uses.
  void stop();
  // As WebServer::watch_readable: the LCM socket handled on this server's I/O thread.
  void watch_readable(int fd, std::function<void()> on_readable) {
    fanout_.watch_readable(fd, std::move(on_readable));
  }
  void send(const SkeletonFrame& f, const LiveSkeleton& skeleton,
            const std::vector<double>& channels);
  const skeleton_io::FanoutStats& stats() const { return fanout_.stats(); }

 private:
  class Session;
  void accept();

  BvhLineFormat format_;
  size_t capacity_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  skeleton_io::Fanout fanout_;
  std::shared_ptr<const std::string> header_;  // read and written on the I/O thread only
  int header_generation_ = 0;                  // producer thread: LiveSkeleton::generation sent
  std::string scratch_, line_;
  int port_ = 0;
  std::thread thread_;
};

class BvhUdpOutput {
 public:
  BvhUdpOutput(const std::string& host, int port, BvhLineFormat format);
  void send(const std::vector<double>& channels);
  int64_t sent() const { return sent_; }
  int64_t failed() const { return failed_; }

 private:
  BvhLineFormat format_;
  boost::asio::io_context io_;
  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint to_;
  std::string scratch_, line_;
  int64_t sent_ = 0, failed_ = 0;
};

}  // namespace hullpose::stream
