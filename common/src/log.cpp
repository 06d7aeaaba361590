#include "hullpose/common/log.hpp"

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "hullpose/common/check.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::log {
namespace {

struct Registry {
  std::mutex mutex;
  std::vector<Category*> categories;
  std::vector<std::pair<std::string, Level>> rules;  // last matching rule wins; "*" matches all
};

Registry& registry() {
  static Registry r;
  return r;
}

Level parse_level(std::string_view text) {
  if (text == "debug") return Level::Debug;
  if (text == "info") return Level::Info;
  if (text == "warn" || text == "warning") return Level::Warn;
  if (text == "error") return Level::Error;
  if (text == "off") return Level::Off;
  HULLPOSE_THROW("log level '" << text << "' is not one of debug, info, warn, error, off");
}

Level level_for(const Registry& r, std::string_view name) {
  Level level = Level::Info;
  for (const auto& [pattern, rule_level] : r.rules)
    if (pattern == "*" || pattern == name) level = rule_level;
  return level;
}

const char* level_tag(Level level) {
  switch (level) {
    case Level::Debug:
      return "DEBUG";
    case Level::Info:
      return "INFO";
    case Level::Warn:
      return "WARN";
    case Level::Error:
      return "ERROR";
    case Level::Off:
      break;
  }
  return "";
}

}  // namespace

Category::Category(const char* name) : name_(name), level_(static_cast<int>(Level::Info)) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  set_level(level_for(r, name_));
  r.categories.push_back(this);
}

void set_levels(std::string_view spec) {
  std::vector<std::pair<std::string, Level>> rules;
  while (!spec.empty()) {
    const size_t comma = spec.find(',');
    std::string_view item = spec.substr(0, comma);
    spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
    if (item.empty()) continue;
    const size_t colon = item.find(':');
    HULLPOSE_THROW_UNLESS(colon != std::string_view::npos,
                          "log spec item '" << item << "' must be name:level");
    rules.emplace_back(std::string(item.substr(0, colon)), parse_level(item.substr(colon + 1)));
  }
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  r.rules = std::move(rules);
  for (Category* c : r.categories) c->set_level(level_for(r, c->name()));
}

void set_levels_from_env() {
  const char* spec = std::getenv("HULLPOSE_LOG");
  if (!spec) return;
  try {
    set_levels(spec);
  } catch (const Error& e) {
    HULLPOSE_THROW("HULLPOSE_LOG: " << e.what());
  }
}

Message::~Message() {
  const int64_t us = realtime_utime();
  const std::string text = stream_.str();
  // One fprintf per line keeps lines from different threads whole.
  std::fprintf(stderr, "[%lld.%06lld] %s %s: %s\n", static_cast<long long>(us / 1'000'000),
               static_cast<long long>(us % 1'000'000), level_tag(level_), category_.name(),
               text.c_str());
}

}  // namespace hullpose::log
