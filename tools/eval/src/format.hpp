#pragma once
// Number formatting shared by the table, the JSON and the HTML report.
#include <cmath>
#include <cstdio>
#include <string>

namespace hullpose::eval {

// `v` with `decimals` decimals, `nan_text` if not finite; a value that rounds to zero prints
// without a sign ("0.0", never "-0.0").
inline std::string fixed(double v, int decimals, const char* nan_text) {
  if (!std::isfinite(v)) return nan_text;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  if (buf[0] == '-' && std::string(buf + 1).find_first_not_of("0.") == std::string::npos)
    return buf + 1;
  return buf;
}

}  // namespace hullpose::eval
