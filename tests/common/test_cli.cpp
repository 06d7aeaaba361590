#include <catch2/catch.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"

using hullpose::cli::CommandLine;

namespace {
struct Parsed {
  std::string name = "default";
  double rate = 30;
  int count = 0;
  long long big = 0;
  uint64_t seed = 1;
  bool live = false;
  std::vector<std::string> list;
};

bool parse(Parsed& p, const std::vector<const char*>& options) {
  std::vector<const char*> args{"prog"};
  args.reserve(options.size() + 1);
  for (const char* o : options) args.push_back(o);
  CommandLine cl("usage: prog [options]\n");
  cl.option("--name", p.name)
      .option("--rate", p.rate)
      .option("--count", p.count)
      .option("--big", p.big)
      .option("--seed", p.seed)
      .option("--item", [&p](const std::string& v) { p.list.push_back(v); })
      .flag("--live", p.live);
  return cl.parse(static_cast<int>(args.size()), args.data());
}

std::string error_of(const std::vector<const char*>& args) {
  Parsed p;
  try {
    (void)parse(p, args);
  } catch (const hullpose::Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("command line: typed options, switches, repeated handlers, defaults kept") {
  Parsed p;
  REQUIRE(parse(p, {"--rate", "12.5", "--count", "-3", "--live", "--item", "a", "--item", "b",
                    "--seed", "18446744073709551615"}));
  CHECK(p.name == "default");
  CHECK(p.rate == 12.5);
  CHECK(p.count == -3);
  CHECK(p.live);
  CHECK(p.list == std::vector<std::string>{"a", "b"});
  CHECK(p.seed == 18446744073709551615ull);
}

TEST_CASE("command line: --help stops parsing; a value that looks like -h is a value") {
  Parsed p;
  CHECK_FALSE(parse(p, {"--rate", "1", "--help", "--bogus"}));
  CHECK_FALSE(parse(p, {"-h"}));
  CHECK(parse(p, {"--name", "-h"}));
  CHECK(p.name == "-h");
}

TEST_CASE("command line: bad input is an error that names the option") {
  CHECK_THAT(error_of({"--bogus"}), Catch::Contains("unknown option '--bogus'"));
  CHECK_THAT(error_of({"--rate"}), Catch::Contains("option --rate needs a value"));
  CHECK_THAT(error_of({"--rate", "fast"}), Catch::Contains("--rate: 'fast' is not a number"));
  CHECK_THAT(error_of({"--rate", "inf"}), Catch::Contains("not a number"));
  CHECK_THAT(error_of({"--rate", "3x"}), Catch::Contains("not a number"));
  CHECK_THAT(error_of({"--count", "1.5"}), Catch::Contains("--count: '1.5' is not an integer"));
  CHECK_THAT(error_of({"--count", "99999999999"}), Catch::Contains("out of range"));
  CHECK_THAT(error_of({"--big", ""}), Catch::Contains("not an integer"));
  CHECK_THAT(error_of({"--seed", "-1"}), Catch::Contains("not a non-negative integer"));
}
