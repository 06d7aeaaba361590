#pragma once
#include <string>
#include <string_view>

namespace hullpose {

// How a trigger line is named, at both of its ends: the camera node's input (trigger.edges) and
// the trigger master's output (--line). One parser, so the two ends accept the same names.
//   gpiod:CHIP:OFFSET  a GPIO line through libgpiod (CHIP: /dev/gpiochipN, gpiochipN or a label)
//   wire:PATH          the simulated wire (a Unix socket the master serves)
//   sim                no line at all (the master only; where the caller allows it)
struct TriggerLineSpec {
  enum class Kind { kSim, kWire, kGpiod };
  Kind kind = Kind::kSim;
  std::string path;     // kWire
  std::string chip;     // kGpiod
  unsigned offset = 0;  // kGpiod: the line's number on the chip
};

// Throws hullpose::Error naming `what` ("trigger input", "trigger line") and the spec.
TriggerLineSpec parse_trigger_line_spec(const std::string& spec, std::string_view what,
                                        bool sim_allowed);

// The error for a gpiod: line in a build without libgpiod; `instead` is what to use instead.
[[noreturn]] void throw_no_libgpiod(const std::string& spec, std::string_view what,
                                    std::string_view instead);

}  // namespace hullpose
