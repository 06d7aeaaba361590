#include "hullpose/common/cli.hpp"

#include <charconv>
#include <cmath>
#include <iostream>
#include <limits>

#include "hullpose/common/check.hpp"

namespace hullpose::cli {

double parse_double(std::string_view what, std::string_view text) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  HULLPOSE_THROW_UNLESS(
      !text.empty() && ec == std::errc() && end == text.data() + text.size() && std::isfinite(v),
      what << ": '" << text << "' is not a number");
  return v;
}

long long parse_integer(std::string_view what, std::string_view text) {
  long long v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  HULLPOSE_THROW_UNLESS(!text.empty() && ec == std::errc() && end == text.data() + text.size(),
                        what << ": '" << text << "' is not an integer");
  return v;
}

CommandLine& CommandLine::add(std::string name, bool takes_value,
                              std::function<void(const std::string&)> set) {
  specs_.push_back({std::move(name), takes_value, std::move(set)});
  return *this;
}

CommandLine& CommandLine::option(std::string name, std::string& out) {
  return add(std::move(name), true, [&out](const std::string& v) { out = v; });
}

CommandLine& CommandLine::option(std::string name, double& out) {
  return add(name, true, [&out, name](const std::string& v) { out = parse_double(name, v); });
}

CommandLine& CommandLine::option(std::string name, long long& out) {
  return add(name, true, [&out, name](const std::string& v) { out = parse_integer(name, v); });
}

CommandLine& CommandLine::option(std::string name, int& out) {
  return add(name, true, [&out, name](const std::string& v) {
    const long long x = parse_integer(name, v);
    HULLPOSE_THROW_UNLESS(
        x >= std::numeric_limits<int>::min() && x <= std::numeric_limits<int>::max(),
        name << ": " << v << " is out of range");
    out = static_cast<int>(x);
  });
}

CommandLine& CommandLine::option(std::string name, uint64_t& out) {
  return add(name, true, [&out, name](const std::string& v) {
    uint64_t x = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    HULLPOSE_THROW_UNLESS(!v.empty() && ec == std::errc() && end == v.data() + v.size(),
                          name << ": '" << v << "' is not a non-negative integer");
    out = x;
  });
}

CommandLine& CommandLine::option(std::string name, std::function<void(const std::string&)> handle) {
  return add(std::move(name), true, std::move(handle));
}

CommandLine& CommandLine::flag(std::string name, bool& out) {
  return add(std::move(name), false, [&out](const std::string&) { out = true; });
}

CommandLine& CommandLine::flag(std::string name, std::function<void()> on) {
  return add(std::move(name), false, [on = std::move(on)](const std::string&) { on(); });
}

bool CommandLine::parse(int argc, const char* const* argv) const {
  return parse(argc, argv, std::cout);
}

bool CommandLine::parse(int argc, const char* const* argv, std::ostream& help_out) const {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "-h" || a == "--help") {
      help_out << usage_;
      return false;
    }
    const Spec* spec = nullptr;
    for (const Spec& s : specs_)
      if (s.name == a) spec = &s;
    HULLPOSE_THROW_UNLESS(spec != nullptr, "unknown option '" << a << "' (see --help)");
    if (!spec->takes_value) {
      spec->set({});
      continue;
    }
    HULLPOSE_THROW_UNLESS(i + 1 < argc, "option " << a << " needs a value (see --help)");
    spec->set(argv[++i]);
  }
  return true;
}

}  // namespace hullpose::cli
