#pragma once
// hullpose-eval's command line, as a function so tests can run it in-process.
#include <ostream>

namespace hullpose::eval {

// hullpose-eval --gt DIR --est FILE [--json] [--report DIR]. Returns the exit status:
// 0 done, 2 bad command line or input (message on `err`, per docs/errors.md).
int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace hullpose::eval
