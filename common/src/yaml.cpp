#include "hullpose/common/yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "hullpose/common/check.hpp"

namespace hullpose::yaml {

// What the document's readers asked for: mapping keys by their position in the file.
struct Tracker {
  std::string file;
  std::set<int> read;
};

namespace {

std::string child_field(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

// OpenCV's FileStorage writes "%YAML:1.0", which is not a YAML 1.2 directive.
std::string without_opencv_directive(std::string text) {
  if (text.rfind("%YAML:", 0) == 0) {
    const size_t eol = text.find('\n');
    text.replace(0, eol == std::string::npos ? text.size() : eol, "");
  }
  return text;
}

void mark_tree(const YAML::Node& n, std::set<int>& read) {
  if (n.IsMap()) {
    for (const auto& kv : n) {
      read.insert(kv.first.Mark().pos);
      mark_tree(kv.second, read);
    }
  } else if (n.IsSequence()) {
    for (const auto& item : n) mark_tree(item, read);
  }
}

void check_tree(const YAML::Node& n, const Tracker& t, const std::string& field) {
  if (n.IsMap()) {
    for (const auto& kv : n) {
      const std::string key = kv.first.Scalar();
      HULLPOSE_THROW_UNLESS(t.read.count(kv.first.Mark().pos),
                            t.file << ":" << kv.first.Mark().line + 1 << ": "
                                   << child_field(field, key) << ": unknown field");
      check_tree(kv.second, t, child_field(field, key));
    }
  } else if (n.IsSequence()) {
    size_t i = 0;
    for (const auto& item : n) check_tree(item, t, field + "[" + std::to_string(i++) + "]");
  }
}

}  // namespace

Node::Node(std::shared_ptr<Tracker> tracker, std::shared_ptr<YAML::Node> node, std::string field)
    : tracker_(std::move(tracker)), node_(std::move(node)), field_(std::move(field)) {}

int Node::line() const {
  return node_->Mark().line + 1;
}

std::string Node::where() const {
  std::ostringstream o;
  o << tracker_->file;
  if (node_->Mark().line >= 0) o << ":" << line();
  if (!field_.empty()) o << ": " << field_;
  return o.str();
}

bool Node::is_map() const {
  return node_->IsMap();
}
bool Node::is_list() const {
  return node_->IsSequence();
}
bool Node::is_scalar() const {
  return node_->IsScalar();
}

std::optional<Node> Node::get(const std::string& key) const {
  HULLPOSE_THROW_UNLESS(node_->IsMap() || node_->IsNull(), where() << ": must be a mapping");
  if (!node_->IsMap()) return std::nullopt;
  for (const auto& kv : *node_) {
    if (kv.first.Scalar() != key) continue;
    tracker_->read.insert(kv.first.Mark().pos);
    if (kv.second.IsNull()) return std::nullopt;
    return Node(tracker_, std::make_shared<YAML::Node>(kv.second), child_field(field_, key));
  }
  return std::nullopt;
}

Node Node::need(const std::string& key) const {
  std::optional<Node> n = get(key);
  if (!n) {
    std::ostringstream o;
    o << tracker_->file << ":" << line() << ": " << child_field(field_, key)
      << ": missing (required)";
    throw Error(o.str());
  }
  return *n;
}

std::vector<std::string> Node::keys() const {
  std::vector<std::string> out;
  if (node_->IsMap())
    for (const auto& kv : *node_) out.push_back(kv.first.Scalar());
  return out;
}

std::vector<Node> Node::items() const {
  HULLPOSE_THROW_UNLESS(node_->IsSequence(), where() << ": must be a list");
  std::vector<Node> out;
  size_t i = 0;
  for (const auto& item : *node_)
    out.push_back(Node(tracker_, std::make_shared<YAML::Node>(item),
                       field_ + "[" + std::to_string(i++) + "]"));
  return out;
}

size_t Node::size() const {
  return node_->size();
}

std::string Node::text() const {
  HULLPOSE_THROW_UNLESS(node_->IsScalar(), where() << ": must be a scalar (number or text)");
  return node_->Scalar();
}

std::string Node::string() const {
  HULLPOSE_THROW_UNLESS(node_->IsScalar(), where() << ": must be text");
  HULLPOSE_THROW_UNLESS(!node_->Scalar().empty(), where() << ": must not be empty");
  return node_->Scalar();
}

int64_t Node::integer(int64_t min, int64_t max) const {
  HULLPOSE_THROW_UNLESS(node_->IsScalar(), where() << ": must be an integer");
  const std::string& s = node_->Scalar();
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  HULLPOSE_THROW_UNLESS(!s.empty() && ec == std::errc() && end == s.data() + s.size(),
                        where() << ": must be an integer, got '" << s << "'");
  HULLPOSE_THROW_UNLESS(v >= min && v <= max,
                        where() << ": must be in [" << min << ", " << max << "], got " << v);
  return v;
}

int Node::integer() const {
  return static_cast<int>(integer(INT32_MIN, INT32_MAX));
}

double Node::real() const {
  HULLPOSE_THROW_UNLESS(node_->IsScalar(), where() << ": must be a number");
  const std::string& s = node_->Scalar();
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  HULLPOSE_THROW_UNLESS(
      !s.empty() && ec == std::errc() && end == s.data() + s.size() && std::isfinite(v),
      where() << ": must be a number, got '" << s << "'");
  return v;
}

double Node::real(double min, double max) const {
  const double v = real();
  HULLPOSE_THROW_UNLESS(v >= min && v <= max,
                        where() << ": must be in [" << min << ", " << max << "], got " << v);
  return v;
}

bool Node::boolean() const {
  const std::string s = text();
  if (s == "true" || s == "1") return true;
  if (s == "false" || s == "0") return false;
  HULLPOSE_THROW(where() << ": must be true or false, got '" << s << "'");
}

std::vector<double> Node::reals(size_t count) const {
  HULLPOSE_THROW_UNLESS(node_->IsSequence() && node_->size() == count,
                        where() << ": must be a list of " << count << " numbers");
  std::vector<double> out;
  for (const Node& item : items()) out.push_back(item.real());
  return out;
}

int Node::integer_or(const std::string& key, int fallback, int min, int max) const {
  const std::optional<Node> n = get(key);
  return n ? static_cast<int>(n->integer(min, max)) : fallback;
}

std::string Node::string_or(const std::string& key, const std::string& fallback) const {
  const std::optional<Node> n = get(key);
  return n ? n->string() : fallback;
}

void Node::mark_all_read() const {
  mark_tree(*node_, tracker_->read);
}

Document Document::parse(const std::string& text, const std::string& name) {
  Document d;
  d.tracker_ = std::make_shared<Tracker>(Tracker{name, {}});
  try {
    d.root_ = std::make_shared<YAML::Node>(YAML::Load(without_opencv_directive(text)));
  } catch (const YAML::Exception& e) {
    HULLPOSE_THROW(name << ":" << e.mark.line + 1 << ": not valid YAML: " << e.msg);
  }
  HULLPOSE_THROW_UNLESS(d.root_->IsMap(), name << ": top level must be a mapping");
  return d;
}

Document Document::load(const std::filesystem::path& file) {
  HULLPOSE_THROW_UNLESS(std::filesystem::is_regular_file(file), file.string()
                                                                    << ": file not found");
  std::ifstream in(file);
  HULLPOSE_THROW_UNLESS(in, file.string() << ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  return parse(text.str(), file.string());
}

Node Document::root() const {
  return Node(tracker_, root_, "");
}

void Document::check_all_read() const {
  check_tree(*root_, *tracker_, "");
}

}  // namespace hullpose::yaml
