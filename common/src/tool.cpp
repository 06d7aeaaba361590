#include "hullpose/common/tool.hpp"

#include <exception>
#include <iostream>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose {

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
