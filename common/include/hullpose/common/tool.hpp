#pragma once
// The one entry point of every hullpose program. A main() is one line:
//
//   int main(int argc, char** argv) { return hullpose::run_tool("hullpose-x", argc, argv, run); }
//
// run_tool sets the log levels from HULLPOSE_LOG once (a bad spec is a usage error like any
// other), runs `body`, and turns what escapes it into the exit codes of docs/errors.md:
//   hullpose::Error        -> "<tool>: error: <message>",          exit 2 (bad input, named)
//   other std::exception   -> "<tool>: internal error: <message>", exit 3 (a bug or the system)
// `body` returns the exit code (0, or 1 for "ran, but the result is a failure").
#include <atomic>
#include <functional>
#include <iosfwd>

namespace hullpose {

using ToolBody = std::function<int(int argc, const char* const* argv)>;
int run_tool(const char* tool, int argc, const char* const* argv, const ToolBody& body);
// The same, with the error lines written to `err` (tests).
int run_tool(const char* tool, int argc, const char* const* argv, const ToolBody& body,
             std::ostream& err);

// Stopping on SIGINT / SIGTERM, for the programs that run until told to: call
// catch_stop_signals() once set-up is done (a Ctrl-C during set-up still ends the program at
// once), then loop while !stop_requested(). request_stop() is the same from inside the program
// (a 'quit' command); stop_flag() is the flag itself, for loops that take one.
void catch_stop_signals();
bool stop_requested();
void request_stop();
const std::atomic<bool>& stop_flag();

}  // namespace hullpose
