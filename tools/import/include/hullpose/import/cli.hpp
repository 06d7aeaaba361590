#pragma once
// `hullpose-import rig ...` and `hullpose-import silhouettes ...` (tools/import/README.md).
#include <ostream>

namespace hullpose::import {

// Returns the exit status: 0, or 2 after printing a hullpose::Error to `err`.
int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace hullpose::import
