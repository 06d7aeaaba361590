#include "hullpose/common/check.hpp"

#include <cstdio>
#include <cstdlib>

namespace hullpose::detail {

void throw_error(const std::string& message) {
  throw Error(message);
}

void assert_failed(const char* expr, const char* file, int line) {
  std::fprintf(stderr, "hullpose: internal error: %s:%d: assertion failed: %s\n", file, line, expr);
  std::abort();
}

}  // namespace hullpose::detail
