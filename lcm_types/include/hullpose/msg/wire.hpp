#pragma once
// The one way bytes become messages and messages become bytes.
//
// wire::decode runs a bounds check of the LCM encoding BEFORE lcm-gen's decoder: lcm-gen's C++
// decoders trust the length fields (a string length of 0 or less makes std::string::assign throw;
// a negative or huge array size makes std::vector::resize throw or allocate gigabytes before the
// bounds check). The checks (wire.cpp) walk the layout of lcm_types/hullpose_msg/<type>.lcm and
// accept only messages whose lengths are sane and that fill the buffer exactly; keep them in step
// with the .lcm files (tests/rig/test_lcm_wire.cpp encodes every type and checks truncations and
// bad lengths fail).
//
//   hullpose_msg::trigger_t t;
//   if (!wire::decode(bytes, t)) { counters.add("malformed_trigger"); return; }
//   wire::publish(bus, "TRIGGER", t, scratch);
#include <cstddef>
#include <cstdint>
#include <hullpose_msg/hull_t.hpp>
#include <hullpose_msg/node_status_t.hpp>
#include <hullpose_msg/silhouette_t.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <span>
#include <string>
#include <vector>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/counters.hpp"

namespace hullpose::wire {

inline constexpr int32_t kMaxString = 4096;
inline constexpr int32_t kMaxPayload = 1 << 20;
inline constexpr int32_t kMaxJoints = 256;
inline constexpr int32_t kMaxStatusEntries = 1024;

// The bounds check alone, per type.
bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::silhouette_t*);
bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::trigger_t*);
bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::skeleton_t*);
bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::node_status_t*);
bool well_formed(std::span<const uint8_t> bytes, const hullpose_msg::hull_t*);

// True and `out` filled if `bytes` is exactly one well-formed Msg; false (out unspecified) else.
// Reuses out's strings and vectors: no allocation once they have their size.
template <class Msg>
bool decode(std::span<const uint8_t> bytes, Msg& out) {
  if (!well_formed(bytes, static_cast<const Msg*>(nullptr))) return false;
  const int n = static_cast<int>(bytes.size());
  return out.decode(bytes.data(), 0, n) == n;
}

// `handler(const Msg&)` for every message on `channel` that decodes (into `msg`, reused: no
// allocation per message); one that does not is counted in `counters` under `malformed` and
// dropped. `msg` and `counters` outlive the subscription.
template <class Msg, class Handler>
bus::Subscription subscribe(bus::Bus& bus, const std::string& channel, Msg& msg, Counters& counters,
                            const char* malformed, Handler handler, int queue_capacity = 30) {
  return bus.subscribe(
      channel,
      [&msg, &counters, malformed, handler = std::move(handler)](std::span<const uint8_t> bytes,
                                                                 const std::string&) {
        if (!decode(bytes, msg)) {
          counters.add(malformed);
          return;
        }
        handler(static_cast<const Msg&>(msg));
      },
      queue_capacity);
}

// Encodes `msg` into `scratch` (grown when too small, then reused) and publishes it.
template <class Msg>
bool publish(bus::Bus& bus, const std::string& channel, const Msg& msg,
             std::vector<uint8_t>& scratch) {
  const int size = msg.getEncodedSize();
  if (size <= 0) return false;
  if (scratch.size() < static_cast<size_t>(size)) scratch.resize(static_cast<size_t>(size));
  const int n = msg.encode(scratch.data(), 0, size);
  if (n != size) return false;
  return bus.publish(channel, std::span<const uint8_t>(scratch.data(), static_cast<size_t>(n)));
}

template <class Msg>
bool publish(bus::Bus& bus, const std::string& channel, const Msg& msg) {
  std::vector<uint8_t> scratch;
  return publish(bus, channel, msg, scratch);
}

}  // namespace hullpose::wire
