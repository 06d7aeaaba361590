#pragma once
// The GPIO output that carries the trigger pulse to every camera board.
//   gpiod:CHIP:OFFSET  a real line through libgpiod (v1), e.g. gpiod:gpiochip0:17
//   wire:PATH          a simulated wire for a rig simulated on one machine: every rising edge is
//                      sent, stamped with CLOCK_MONOTONIC like a kernel GPIO event, to the camera
//                      nodes connected to the Unix socket PATH (works across network namespaces)
//   sim                records the edges in memory (tests)
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hullpose::sync {

class TriggerLine {
 public:
  virtual ~TriggerLine() = default;
  // Drives the line. Returns the CLOCK_MONOTONIC time (us) the line stamped the edge with (the
  // simulated wire sends that stamp to the nodes), or -1 when it has no stamp of its own.
  virtual int64_t set(bool high) = 0;
  virtual std::string describe() const = 0;
  // The simulated wire only: waits until `nodes` camera nodes are connected, so that a rig
  // started on one machine loses no pulse. A physical line has no listeners to count.
  virtual size_t wait_for_nodes(size_t nodes, int timeout_ms) {
    (void)timeout_ms;
    return nodes;
  }
};

// Throws hullpose::Error naming the spec and the device when the line cannot be opened.
std::unique_ptr<TriggerLine> open_trigger_line(const std::string& spec);

class SimTriggerLine final : public TriggerLine {
 public:
  int64_t set(bool high) override {
    levels_.push_back(high);
    return -1;
  }
  std::string describe() const override { return "sim"; }
  const std::vector<bool>& levels() const { return levels_; }

 private:
  std::vector<bool> levels_;
};

}  // namespace hullpose::sync
