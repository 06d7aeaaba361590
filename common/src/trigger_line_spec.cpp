#include "hullpose/common/trigger_line_spec.hpp"

#include <algorithm>
#include <cctype>

#include "hullpose/common/check.hpp"

namespace hullpose {

TriggerLineSpec parse_trigger_line_spec(const std::string& spec, std::string_view what,
                                        bool sim_allowed) {
  TriggerLineSpec out;
  if (sim_allowed && spec == "sim") return out;
  if (spec.rfind("wire:", 0) == 0) {
    out.kind = TriggerLineSpec::Kind::kWire;
    out.path = spec.substr(5);
    return out;
  }
  if (spec.rfind("gpiod:", 0) == 0) {
    const auto colon = spec.rfind(':');
    HULLPOSE_THROW_UNLESS(colon > 6, what << " '" << spec << "': expected gpiod:CHIP:OFFSET");
    const std::string offset = spec.substr(colon + 1);
    // At most 5 digits: no chip has more lines, and stoul cannot overflow.
    HULLPOSE_THROW_UNLESS(
        !offset.empty() && offset.size() < 6 &&
            std::all_of(offset.begin(), offset.end(), ::isdigit),
        what << " '" << spec << "': offset '" << offset << "' is not a line number");
    out.kind = TriggerLineSpec::Kind::kGpiod;
    out.chip = spec.substr(6, colon - 6);
    out.offset = static_cast<unsigned>(std::stoul(offset));
    return out;
  }
  HULLPOSE_THROW(what << " '" << spec << "': expected gpiod:CHIP:OFFSET"
                      << (sim_allowed ? ", wire:PATH or sim" : " or wire:PATH"));
}

void throw_no_libgpiod(const std::string& spec, std::string_view what, std::string_view instead) {
  HULLPOSE_THROW(what << " '" << spec
                      << "': this build has no libgpiod (install libgpiod-dev and configure "
                         "with -DHULLPOSE_GPIOD=ON); without the trigger GPIO use "
                      << instead);
}

}  // namespace hullpose
