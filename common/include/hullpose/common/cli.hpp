#pragma once
// The one command-line parser of every hullpose program: "--name VALUE" options bound to typed
// fields, and "--name" switches. Bad input — an unknown option, a missing value, a value that is
// not a whole number of the field's type — throws hullpose::Error naming the option
// (docs/errors.md), which run_tool (common/tool.hpp) turns into exit 2; -h/--help prints the
// usage, and parse() returns false so that the program exits 0.
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace hullpose::cli {

class CommandLine {
 public:
  explicit CommandLine(std::string usage) : usage_(std::move(usage)) {}

  CommandLine& option(std::string name, std::string& out);
  CommandLine& option(std::string name, double& out);  // finite numbers only
  CommandLine& option(std::string name, int& out);
  CommandLine& option(std::string name, long long& out);
  CommandLine& option(std::string name, uint64_t& out);
  // For values that need their own parsing (lists, presets); the handler throws hullpose::Error.
  CommandLine& option(std::string name, std::function<void(const std::string&)> handle);
  CommandLine& flag(std::string name, bool& out);
  CommandLine& flag(std::string name, std::function<void()> on);

  // False when -h or --help was given, after printing usage() to `help_out` (stdout): the caller
  // exits 0.
  [[nodiscard]] bool parse(int argc, const char* const* argv) const;
  [[nodiscard]] bool parse(int argc, const char* const* argv, std::ostream& help_out) const;
  const std::string& usage() const { return usage_; }

 private:
  struct Spec {
    std::string name;
    bool takes_value;
    std::function<void(const std::string&)> set;
  };
  CommandLine& add(std::string name, bool takes_value, std::function<void(const std::string&)> set);

  std::string usage_;
  std::vector<Spec> specs_;
};

// A whole finite number, or hullpose::Error naming `what` (an option or field) and the text.
double parse_double(std::string_view what, std::string_view text);
long long parse_integer(std::string_view what, std::string_view text);

}  // namespace hullpose::cli
