#pragma once
// One message to many network receivers (browsers on a WebSocket, BVH clients on TCP) without
// the producer ever waiting on one: publish() only posts to the I/O thread; there each session
// queues the message in its DropOldestQueue and writes when its previous write is done. A slow
// receiver loses its oldest messages (counted), a vanished one is closed and forgotten; memory
// stays at `capacity` messages per session. Sessions and the fanout live on one asio
// io_context run by one thread.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "hullpose/skeleton_io/asio.hpp"
#include "hullpose/skeleton_io/drop_oldest_queue.hpp"

namespace hullpose::skeleton_io {

using Message = std::shared_ptr<const std::string>;

struct FanoutStats {
  std::atomic<int64_t> sessions{0}, accepted{0}, published{0}, sent{0}, dropped{0}, closed{0};
};

class OutboundSession : public std::enable_shared_from_this<OutboundSession> {
 public:
  OutboundSession(FanoutStats& stats, size_t capacity) : stats_(stats), queue_(capacity) {}
  virtual ~OutboundSession() = default;
  // On the I/O thread.
  void deliver(const Message& m) {
    if (closed_) return;
    const int64_t before = queue_.dropped();
    queue_.push(m);
    stats_.dropped += queue_.dropped() - before;
    if (!writing_) write_next();
  }
  void close() {
    if (closed_) return;
    closed_ = true;
    ++stats_.closed;
    do_close();
    if (on_closed_) on_closed_(this);
  }
  void set_on_closed(std::function<void(OutboundSession*)> f) { on_closed_ = std::move(f); }
  size_t queued() const { return queue_.size(); }

 protected:
  // Writes one message and calls done(ok) on the I/O thread when it is on the wire (or failed).
  virtual void async_send(const std::string& m, std::function<void(bool ok)> done) = 0;
  virtual void do_close() = 0;

 private:
  void write_next() {
    if (queue_.empty() || closed_) {
      writing_ = false;
      return;
    }
    writing_ = true;
    current_ = queue_.front();
    queue_.pop();
    async_send(*current_, [self = shared_from_this()](bool ok) {
      self->current_.reset();
      if (!ok) return self->close();
      ++self->stats_.sent;
      self->write_next();
    });
  }

  FanoutStats& stats_;
  DropOldestQueue<Message> queue_;
  Message current_;  // kept alive until its write completes
  bool writing_ = false, closed_ = false;
  std::function<void(OutboundSession*)> on_closed_;
};

class Fanout {
 public:
  explicit Fanout(boost::asio::io_context& io) : io_(io) {}
  // On the I/O thread: the session starts receiving what is published from now on.
  void add(const std::shared_ptr<OutboundSession>& s) {
    s->set_on_closed([this](OutboundSession* gone) {
      for (auto it = sessions_.begin(); it != sessions_.end(); ++it)
        if (it->get() == gone) {
          sessions_.erase(it);
          --stats_.sessions;
          return;
        }
    });
    sessions_.insert(s);
    ++stats_.sessions;
    ++stats_.accepted;
  }
  // Any thread; never blocks. On the I/O thread itself (the LCM socket watched there, see
  // watch_readable) it delivers at once: no hop between threads on the way to the socket.
  void publish(Message m) {
    ++stats_.published;
    boost::asio::dispatch(io_, [this, m = std::move(m)] {
      // deliver() may close (and so erase) a session: walk a copy (its capacity is reused).
      scratch_.assign(sessions_.begin(), sessions_.end());
      for (const auto& s : scratch_) s->deliver(m);
      scratch_.clear();
    });
  }
  // Calls on_readable on the I/O thread whenever `fd` (not owned: e.g. the LCM socket) has
  // data. Call before the I/O thread runs, or from it.
  void watch_readable(int fd, std::function<void()> on_readable) {
    watches_.push_back(std::make_unique<Watch>(io_, fd, std::move(on_readable)));
    watches_.back()->arm();
  }
  // On the I/O thread: stop watching, close every session.
  void close_all() {
    for (auto& w : watches_) w->stop();
    const auto now = sessions_;
    for (const auto& s : now) s->close();
  }
  const FanoutStats& stats() const { return stats_; }
  FanoutStats& stats() { return stats_; }

 private:
  struct Watch {
    Watch(boost::asio::io_context& io, int fd, std::function<void()> f)
        : descriptor(io, fd), on_readable(std::move(f)) {}
    ~Watch() { stop(); }
    void arm() {
      descriptor.async_wait(boost::asio::posix::descriptor_base::wait_read,
                            [this](boost::system::error_code ec) {
                              if (ec) return;
                              on_readable();
                              arm();
                            });
    }
    void stop() {
      if (!descriptor.is_open()) return;
      boost::system::error_code ec;
      descriptor.cancel(ec);
      descriptor.release();  // the fd belongs to its owner (LCM)
    }
    boost::asio::posix::stream_descriptor descriptor;
    std::function<void()> on_readable;
  };

  boost::asio::io_context& io_;
  std::vector<std::unique_ptr<Watch>> watches_;
  std::set<std::shared_ptr<OutboundSession>> sessions_;
  std::vector<std::shared_ptr<OutboundSession>> scratch_;
  FanoutStats stats_;
};

// Opens `acceptor` on bind:port (port 0: any free one) and returns the port; hullpose::Error
// naming `option` (the command-line option that asked for it) when it cannot.
int listen_on(boost::asio::ip::tcp::acceptor& acceptor, const std::string& bind, int port,
              const std::string& option);
// From any thread but the I/O one: on the I/O thread close the acceptor and every session, then
// stop; join the thread. Does nothing once joined.
void stop_service(boost::asio::io_context& io, boost::asio::ip::tcp::acceptor& acceptor,
                  Fanout& fanout, std::thread& thread);

}  // namespace hullpose::skeleton_io
