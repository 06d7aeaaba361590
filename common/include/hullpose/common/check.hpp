#pragma once
// Error policy (docs/errors.md):
//  - Bad user input (config, rig file, command line, files on disk) throws hullpose::Error
//    through HULLPOSE_THROW_UNLESS with a message that names the thing at fault; main()
//    catches it, prints it and exits non-zero.
//  - Bugs (broken invariants of our own code) use HULLPOSE_ASSERT, which aborts.
//  - Per-frame paths never throw for bad data from the network: they count and log a drop
//    (see hullpose::DropCounters).
#include <sstream>
#include <stdexcept>
#include <string>

namespace hullpose {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
[[noreturn]] void throw_error(const std::string& message);
[[noreturn]] void assert_failed(const char* expr, const char* file, int line);
}  // namespace detail

}  // namespace hullpose

// HULLPOSE_THROW_UNLESS(fx > 0, "camera " << id << ": fx must be positive, got " << fx);
#define HULLPOSE_THROW_UNLESS(cond, stream_expr)            \
  do {                                                      \
    if (!(cond)) {                                          \
      std::ostringstream hullpose_msg_;                     \
      hullpose_msg_ << stream_expr;                         \
      ::hullpose::detail::throw_error(hullpose_msg_.str()); \
    }                                                       \
  } while (0)

// Unconditional, so that even an unoptimised build sees the function end here (-Wreturn-type).
#define HULLPOSE_THROW(stream_expr)                       \
  do {                                                    \
    std::ostringstream hullpose_msg_;                     \
    hullpose_msg_ << stream_expr;                         \
    ::hullpose::detail::throw_error(hullpose_msg_.str()); \
  } while (0)

#define HULLPOSE_ASSERT(cond)                                                  \
  do {                                                                         \
    if (!(cond)) ::hullpose::detail::assert_failed(#cond, __FILE__, __LINE__); \
  } while (0)
