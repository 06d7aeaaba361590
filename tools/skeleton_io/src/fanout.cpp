#include "hullpose/skeleton_io/fanout.hpp"

#include "hullpose/common/check.hpp"

namespace hullpose::skeleton_io {

namespace asio = boost::asio;
using asio::ip::tcp;

int listen_on(tcp::acceptor& acceptor, const std::string& bind, int port,
              const std::string& option) {
  boost::system::error_code ec;
  const asio::ip::address address = asio::ip::make_address(bind, ec);
  HULLPOSE_THROW_UNLESS(!ec, option << ": '" << bind << "' is not an IP address");
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(port));
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  HULLPOSE_THROW_UNLESS(
      !ec, option << ": cannot listen on " << bind << ":" << port << ": " << ec.message());
  return acceptor.local_endpoint().port();
}

void stop_service(asio::io_context& io, tcp::acceptor& acceptor, Fanout& fanout,
                  std::thread& thread) {
  if (!thread.joinable()) return;
  asio::post(io, [&] {
    boost::system::error_code ec;
    acceptor.close(ec);
    fanout.close_all();
    io.stop();
  });
  thread.join();
}

}  // namespace hullpose::skeleton_io
