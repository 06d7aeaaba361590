#pragma once
// The named parameters of one stage (a frame-source backend or a background-subtraction
// method), read from the node's YAML file as a flat mapping of scalars.
//
// Each stage reads its parameters through the typed getters, which check type and range and
// name the field in errors ("camera.yaml: bgs.params.detection_rate: must be in [0.5, 1], got 2").
// Unknown keys are errors too (expect_all_used): a typo must not silently fall back to a default.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hullpose::camera_node {

class Params {
 public:
  Params() = default;
  // scope: how errors name the mapping, e.g. "camera.yaml: source".
  explicit Params(std::string scope) : scope_(std::move(scope)) {}

  void set(std::string key, std::string value);
  bool has(std::string_view key) const;
  const std::string& scope() const { return scope_; }

  std::string get_string(std::string_view key, std::string_view fallback) const;
  std::string require_string(std::string_view key) const;
  int get_int(std::string_view key, int fallback, int min, int max) const;
  double get_double(std::string_view key, double fallback, double min, double max) const;
  bool get_bool(std::string_view key, bool fallback) const;

  // Throws naming every key no getter asked for.
  void expect_all_used() const;

 private:
  const std::string* find(std::string_view key) const;
  std::string field(std::string_view key) const;

  std::string scope_;
  std::vector<std::pair<std::string, std::string>> values_;
  mutable std::vector<bool> used_;
};

}  // namespace hullpose::camera_node
