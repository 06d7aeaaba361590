#include "hullpose/import/pattern.hpp"

#include <cstdio>

#include "hullpose/common/check.hpp"

namespace hullpose::import {

std::string expand(const std::string& pattern, char letter, int value, bool required) {
  std::string out;
  bool found = false;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] == '{' && i + 1 < pattern.size() && pattern[i + 1] == letter) {
      size_t j = i + 1;
      while (j < pattern.size() && pattern[j] == letter) ++j;
      if (j < pattern.size() && pattern[j] == '}') {
        const int digits = static_cast<int>(j - i - 1);
        char buf[32];
        std::snprintf(buf, sizeof buf, "%0*d", digits == 1 ? 1 : digits, value);
        out += buf;
        i = j;
        found = true;
        continue;
      }
    }
    out += pattern[i];
  }
  HULLPOSE_THROW_UNLESS(found || !required, "pattern '" << pattern << "' has no {" << letter
                                                        << "} field (e.g. {" << letter << "} or {"
                                                        << letter << letter << letter << letter
                                                        << "})");
  return out;
}

}  // namespace hullpose::import
