#pragma once
// The one YAML reader (yaml-cpp) for hullpose's configuration files: the rig file and the
// camera node's config. Every error names the file, the line and the field:
//
//   "node.yaml:7: bgs.learn_frames: must be an integer, got 'many'"
//
// and keys nobody read are errors too (check_all_read): a typo must not silently fall back to a
// default. OpenCV's "%YAML:1.0" first line (files written by earlier versions) is accepted.
//
//   yaml::Document doc = yaml::Document::load(path);
//   yaml::Node root = doc.root();
//   int id = root.need("camera_id").integer(0, 63);
//   std::string name = root.get_or("name", std::string("cam"));
//   doc.check_all_read();
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace hullpose::yaml {

struct Tracker;

class Node {
 public:
  // "file:line: field" for error messages.
  std::string where() const;
  const std::string& field() const { return field_; }
  int line() const;

  bool is_map() const;
  bool is_list() const;
  bool is_scalar() const;

  // A key of this mapping: need() throws when it is missing, get() returns nullopt.
  Node need(const std::string& key) const;
  std::optional<Node> get(const std::string& key) const;
  std::vector<std::string> keys() const;  // mapping keys, in file order
  // List items.
  std::vector<Node> items() const;
  size_t size() const;

  // Scalars, checked: throw hullpose::Error naming where() and what was found.
  std::string text() const;    // any scalar, as written
  std::string string() const;  // a non-empty scalar
  int64_t integer(int64_t min, int64_t max) const;
  int integer() const;
  double real() const;  // finite
  double real(double min, double max) const;
  bool boolean() const;
  std::vector<double> reals(size_t count) const;  // a list of exactly `count` numbers

  // Shorthands for optional keys.
  int integer_or(const std::string& key, int fallback, int min, int max) const;
  std::string string_or(const std::string& key, const std::string& fallback) const;

  // This mapping's keys are all read from now on (they are handed on, e.g. as stage parameters).
  void mark_all_read() const;

 private:
  friend class Document;
  Node(std::shared_ptr<Tracker> tracker, std::shared_ptr<YAML::Node> node, std::string field);
  std::shared_ptr<Tracker> tracker_;
  std::shared_ptr<YAML::Node> node_;
  std::string field_;
};

class Document {
 public:
  // Throws hullpose::Error "FILE: not found" / "FILE:LINE: not valid YAML: ..." / top level not a
  // mapping.
  static Document load(const std::filesystem::path& file);
  static Document parse(const std::string& text, const std::string& name);
  Node root() const;
  // Throws naming the first key (file:line, field) that no reader asked for.
  void check_all_read() const;

 private:
  std::shared_ptr<Tracker> tracker_;
  std::shared_ptr<YAML::Node> root_;
};

}  // namespace hullpose::yaml
