#pragma once
// File-name patterns of the import commands: `{N}` is the camera number and `{F}` the frame
// number, each as a plain integer, or zero-padded to as many digits as letters (`{NN}` -> 07,
// `{FFFF}` -> 0042). Example: "silhouettes/camera{N}_{FFFF}.png".
#include <string>

namespace hullpose::import {

// `pattern` with every `{L...}` field of letter `letter` replaced by `value`; other text as is.
// Throws hullpose::Error if the pattern has no such field and `required` is set.
std::string expand(const std::string& pattern, char letter, int value, bool required = true);

}  // namespace hullpose::import
