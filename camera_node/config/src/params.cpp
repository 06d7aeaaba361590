#include "hullpose/camera_node/params.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "hullpose/common/check.hpp"

namespace hullpose::camera_node {

void Params::set(std::string key, std::string value) {
  for (size_t i = 0; i < values_.size(); ++i) {
    if (values_[i].first == key) {
      values_[i].second = std::move(value);
      return;
    }
  }
  values_.emplace_back(std::move(key), std::move(value));
  used_.push_back(false);
}

bool Params::has(std::string_view key) const {
  return find(key) != nullptr;
}

const std::string* Params::find(std::string_view key) const {
  for (size_t i = 0; i < values_.size(); ++i) {
    if (values_[i].first == key) {
      used_[i] = true;
      return &values_[i].second;
    }
  }
  return nullptr;
}

std::string Params::field(std::string_view key) const {
  return scope_.empty() ? std::string(key) : scope_ + "." + std::string(key);
}

std::string Params::get_string(std::string_view key, std::string_view fallback) const {
  const std::string* v = find(key);
  return v ? *v : std::string(fallback);
}

std::string Params::require_string(std::string_view key) const {
  const std::string* v = find(key);
  HULLPOSE_THROW_UNLESS(v && !v->empty(), field(key) << ": missing (required)");
  return *v;
}

int Params::get_int(std::string_view key, int fallback, int min, int max) const {
  const std::string* v = find(key);
  if (!v) return fallback;
  int out = 0;
  const char* end = v->data() + v->size();
  auto [ptr, ec] = std::from_chars(v->data(), end, out);
  HULLPOSE_THROW_UNLESS(ec == std::errc() && ptr == end,
                        field(key) << ": must be an integer, got '" << *v << "'");
  HULLPOSE_THROW_UNLESS(out >= min && out <= max,
                        field(key) << ": must be in [" << min << ", " << max << "], got " << out);
  return out;
}

double Params::get_double(std::string_view key, double fallback, double min, double max) const {
  const std::string* v = find(key);
  if (!v) return fallback;
  char* end = nullptr;
  const double out = std::strtod(v->c_str(), &end);
  HULLPOSE_THROW_UNLESS(!v->empty() && end == v->c_str() + v->size() && std::isfinite(out),
                        field(key) << ": must be a number, got '" << *v << "'");
  HULLPOSE_THROW_UNLESS(out >= min && out <= max,
                        field(key) << ": must be in [" << min << ", " << max << "], got " << out);
  return out;
}

bool Params::get_bool(std::string_view key, bool fallback) const {
  const std::string* v = find(key);
  if (!v) return fallback;
  if (*v == "true" || *v == "1") return true;
  if (*v == "false" || *v == "0") return false;
  HULLPOSE_THROW(field(key) << ": must be true or false, got '" << *v << "'");
}

void Params::expect_all_used() const {
  std::string unknown;
  for (size_t i = 0; i < values_.size(); ++i) {
    if (used_[i]) continue;
    unknown += unknown.empty() ? "" : ", ";
    unknown += values_[i].first;
  }
  HULLPOSE_THROW_UNLESS(unknown.empty(), scope_ << ": unknown parameter(s): " << unknown);
}

}  // namespace hullpose::camera_node
