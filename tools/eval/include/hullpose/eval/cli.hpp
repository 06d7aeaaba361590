#pragma once
// hullpose-eval's command line, as a function so tests can run it in-process (inside run_tool,
// as main() does).
#include <ostream>

namespace hullpose::eval {

// hullpose-eval --gt DIR --est FILE [--json] [--report DIR]: writes the table or JSON to `out`
// and returns 0. Throws hullpose::Error on a bad command line or input (run_tool: exit 2).
int run_cli(int argc, const char* const* argv, std::ostream& out);

}  // namespace hullpose::eval
