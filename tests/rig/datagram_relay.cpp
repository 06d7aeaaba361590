// A reordering and duplicating hop for the fault tests (tests/system/fault_matrix_test.sh).
// This kernel has no netem qdisc (tc qdisc add ... netem fails with "Specified qdisc kind is
// unknown") and nftables can drop or copy packets but not hold them back, so the fusion host
// listens on a group of its own and this relay, in the host's namespace, forwards the rig's
// datagrams to it: every SWAP-th datagram is held back and sent after the next one, every
// DUP-th is sent twice. The pattern counts datagrams, so it does not depend on timing (a held
// datagram with no successor within 20 ms is sent alone).
//   rig_datagram_relay --from GROUP:PORT --to GROUP:PORT [--swap-every N] [--duplicate-every M]
//                      [--duration-s S]
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"

namespace {
sockaddr_in parse_endpoint(const std::string& what, const std::string& text) {
  const auto colon = text.rfind(':');
  HULLPOSE_THROW_UNLESS(colon != std::string::npos,
                        what << ": expected GROUP:PORT, got '" << text << "'");
  sockaddr_in a{};
  a.sin_family = AF_INET;
  HULLPOSE_THROW_UNLESS(inet_pton(AF_INET, text.substr(0, colon).c_str(), &a.sin_addr) == 1,
                        what << ": '" << text.substr(0, colon) << "' is not an IPv4 address");
  const long long port = hullpose::cli::parse_integer(what, text.substr(colon + 1));
  HULLPOSE_THROW_UNLESS(port > 0 && port < 65536, what << ": port " << port << " out of range");
  a.sin_port = htons(static_cast<uint16_t>(port));
  return a;
}
}  // namespace

int main(int argc, char** argv) {
  return hullpose::run_tool("rig_datagram_relay", argc, argv, [](int c, const char* const* v) {
    std::string from_text, to_text;
    long long swap_every = 0, dup_every = 0;
    double duration_s = 3600;
    hullpose::cli::CommandLine cl(
        "usage: rig_datagram_relay --from GROUP:PORT --to GROUP:PORT [--swap-every N] "
        "[--duplicate-every M] "
        "[--duration-s S]\n");
    cl.option("--from", from_text)
        .option("--to", to_text)
        .option("--swap-every", swap_every)
        .option("--duplicate-every", dup_every)
        .option("--duration-s", duration_s);
    if (!cl.parse(c, v)) return 0;
    const sockaddr_in from = parse_endpoint("--from", from_text),
                      to = parse_endpoint("--to", to_text);
    const int in = socket(AF_INET, SOCK_DGRAM, 0), out = socket(AF_INET, SOCK_DGRAM, 0);
    HULLPOSE_THROW_UNLESS(in >= 0 && out >= 0, "cannot create UDP sockets");
    const int one = 1;
    setsockopt(in, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    setsockopt(in, SOL_SOCKET, SO_REUSEPORT, &one, sizeof one);
    sockaddr_in bind_addr = from;
    bind_addr.sin_addr.s_addr = htonl(INADDR_ANY);
    HULLPOSE_THROW_UNLESS(bind(in, reinterpret_cast<sockaddr*>(&bind_addr), sizeof bind_addr) == 0,
                          "cannot bind port " << ntohs(from.sin_port));
    ip_mreq mreq{};
    mreq.imr_multiaddr = from.sin_addr;
    mreq.imr_interface.s_addr = htonl(INADDR_ANY);
    HULLPOSE_THROW_UNLESS(setsockopt(in, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof mreq) == 0,
                          "cannot join " << from_text);
    // Only to this host's own receivers: TTL 0 with loopback.
    const unsigned char ttl = 0, loop = 1;
    setsockopt(out, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
    setsockopt(out, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop);
    hullpose::catch_stop_signals();

    std::vector<uint8_t> buf(65536), held;
    long long received = 0, swapped = 0, duplicated = 0;
    const auto send = [&](const std::vector<uint8_t>& b, size_t n) {
      sendto(out, b.data(), n, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    };
    const int64_t end = hullpose::monotonic_us() + static_cast<int64_t>(duration_s * 1e6);
    while (!hullpose::stop_requested() && hullpose::monotonic_us() < end) {
      pollfd p{in, POLLIN, 0};
      if (poll(&p, 1, 20) <= 0) {
        if (!held.empty()) send(held, held.size()), held.clear();
        continue;
      }
      const ssize_t n = recv(in, buf.data(), buf.size(), 0);
      if (n <= 0) continue;
      ++received;
      const auto size = static_cast<size_t>(n);
      if (held.empty() && swap_every > 0 && received % swap_every == 0) {
        held.assign(buf.begin(), buf.begin() + n);
        ++swapped;
        continue;
      }
      send(buf, size);
      if (dup_every > 0 && received % dup_every == 0) send(buf, size), ++duplicated;
      if (!held.empty()) send(held, held.size()), held.clear();
    }
    std::fprintf(
        stderr,
        "rig_datagram_relay: %lld datagrams, %lld sent after their successor, %lld sent twice\n",
        received, swapped, duplicated);
    close(in);
    close(out);
    return 0;
  });
}
