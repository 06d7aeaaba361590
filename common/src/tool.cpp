#include "hullpose/common/tool.hpp"

#include <csignal>
#include <exception>
#include <iostream>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose {
namespace {

// Lock-free, so the signal handler may set it.
std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free);

void on_stop_signal(int) {
  g_stop.store(true);
}

}  // namespace

void catch_stop_signals() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

bool stop_requested() {
  return g_stop.load();
}

void request_stop() {
  g_stop.store(true);
}

const std::atomic<bool>& stop_flag() {
  return g_stop;
}

int run_tool(const char* tool, int argc, const char* const* argv, const ToolBody& body,
             std::ostream& err) {
  try {
    log::set_levels_from_env();
    return body(argc, argv);
  } catch (const Error& e) {
    err << tool << ": error: " << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    err << tool << ": internal error: " << e.what() << std::endl;
    return 3;
  }
}

int run_tool(const char* tool, int argc, const char* const* argv, const ToolBody& body) {
  return run_tool(tool, argc, argv, body, std::cerr);
}

}  // namespace hullpose
