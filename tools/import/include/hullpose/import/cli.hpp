#pragma once
// `hullpose-import rig ...` and `hullpose-import silhouettes ...` (tools/import/README.md).
#include <ostream>

namespace hullpose::import {

// Returns the exit status (0); throws hullpose::Error on bad input (run_tool makes it exit 2).
int run_cli(int argc, const char* const* argv, std::ostream& out);

}  // namespace hullpose::import
