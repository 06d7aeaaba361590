// The pieces every program shares at its top: the stop facility and the trigger line names.
#include <catch2/catch.hpp>
#include <csignal>

#include "hullpose/common/check.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/common/trigger_line_spec.hpp"

using hullpose::TriggerLineSpec;

TEST_CASE("trigger line names: gpiod, wire and, where allowed, sim") {
  const TriggerLineSpec g = hullpose::parse_trigger_line_spec("gpiod:gpiochip0:17", "x", false);
  CHECK(g.kind == TriggerLineSpec::Kind::kGpiod);
  CHECK(g.chip == "gpiochip0");
  CHECK(g.offset == 17);
  const TriggerLineSpec d = hullpose::parse_trigger_line_spec("gpiod:/dev/gpiochip4:3", "x", false);
  CHECK(d.chip == "/dev/gpiochip4");
  CHECK(d.offset == 3);
  const TriggerLineSpec w = hullpose::parse_trigger_line_spec("wire:/tmp/a.sock", "x", false);
  CHECK(w.kind == TriggerLineSpec::Kind::kWire);
  CHECK(w.path == "/tmp/a.sock");
  CHECK(hullpose::parse_trigger_line_spec("sim", "x", true).kind == TriggerLineSpec::Kind::kSim);

  using Catch::Contains;
  CHECK_THROWS_WITH(hullpose::parse_trigger_line_spec("sim", "trigger input", false),
                    Contains("trigger input 'sim': expected gpiod:CHIP:OFFSET or wire:PATH"));
  CHECK_THROWS_WITH(hullpose::parse_trigger_line_spec("usb", "trigger line", true),
                    Contains("expected gpiod:CHIP:OFFSET, wire:PATH or sim"));
  CHECK_THROWS_WITH(hullpose::parse_trigger_line_spec("gpiod:17", "x", false),
                    Contains("expected gpiod:CHIP:OFFSET"));
  CHECK_THROWS_WITH(hullpose::parse_trigger_line_spec("gpiod::17", "x", false),
                    Contains("expected gpiod:CHIP:OFFSET"));
  for (const char* bad : {"gpiod:chip:x", "gpiod:chip:", "gpiod:chip:123456", "gpiod:chip:-1"})
    CHECK_THROWS_WITH(hullpose::parse_trigger_line_spec(bad, "x", false),
                      Contains("is not a line number"));
  CHECK_THROWS_WITH(hullpose::throw_no_libgpiod("gpiod:c:1", "trigger input", "wire:PATH"),
                    Contains("this build has no libgpiod") && Contains("use wire:PATH"));
}

TEST_CASE("SIGINT after catch_stop_signals asks the loop to stop, as request_stop does") {
  // The flag is process-wide and never cleared: this is the only test here that sets it.
  REQUIRE_FALSE(hullpose::stop_requested());
  hullpose::catch_stop_signals();
  std::raise(SIGINT);
  CHECK(hullpose::stop_requested());
  CHECK(hullpose::stop_flag().load());
  hullpose::request_stop();
  CHECK(hullpose::stop_requested());
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}
