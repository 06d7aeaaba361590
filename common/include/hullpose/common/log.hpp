#pragma once
// Log categories with runtime levels, in the manner of libcamera's LOG(Category, Level).
//
//   HULLPOSE_LOG_CATEGORY(Carve, "carve");        // once, in one .cpp
//   HULLPOSE_LOG(Carve, Info) << "resolution " << n;
//
// Levels are set at run time with HULLPOSE_LOG="carve:debug,lcm:warn,*:info" (default *:info),
// read once by run_tool (common/tool.hpp) at program start, or with hullpose::log::set_levels().
// Output goes to stderr, one line per message, thread-safe.
#include <atomic>
#include <sstream>
#include <string>
#include <string_view>

namespace hullpose::log {

enum class Level : int { Debug = 0, Info = 1, Warn = 2, Error = 3, Off = 4 };

class Category {
 public:
  explicit Category(const char* name);
  const char* name() const { return name_; }
  bool enabled(Level level) const {
    return static_cast<int>(level) >= level_.load(std::memory_order_relaxed);
  }
  void set_level(Level level) { level_.store(static_cast<int>(level), std::memory_order_relaxed); }

 private:
  const char* name_;
  std::atomic<int> level_;
};

// Parses "name:level,name:level,*:level"; throws hullpose::Error on a bad spec.
void set_levels(std::string_view spec);
// set_levels(HULLPOSE_LOG) if it is set; a bad spec throws hullpose::Error naming HULLPOSE_LOG.
void set_levels_from_env();

class Message {
 public:
  Message(const Category& category, Level level) : category_(category), level_(level) {}
  ~Message();
  Message(const Message&) = delete;
  Message& operator=(const Message&) = delete;
  template <typename T>
  Message& operator<<(const T& value) {
    stream_ << value;
    return *this;
  }

 private:
  const Category& category_;
  Level level_;
  std::ostringstream stream_;
};

}  // namespace hullpose::log

#define HULLPOSE_LOG_CATEGORY(ident, name)            \
  ::hullpose::log::Category& log_category_##ident() { \
    static ::hullpose::log::Category category(name);  \
    return category;                                  \
  }
#define HULLPOSE_LOG_DECLARE_CATEGORY(ident) ::hullpose::log::Category& log_category_##ident();

#define HULLPOSE_LOG(ident, level)                                      \
  if (!log_category_##ident().enabled(::hullpose::log::Level::level)) { \
  } else                                                                \
    ::hullpose::log::Message(log_category_##ident(), ::hullpose::log::Level::level)
