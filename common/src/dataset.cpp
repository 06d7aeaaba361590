#include "hullpose/common/dataset.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hullpose/common/check.hpp"

namespace hullpose {
namespace fs = std::filesystem;

namespace {

std::string frame_name(const char* prefix, int index) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%s_%06d.png", prefix, index);
  return buf;
}

std::string joint_columns() {
  std::string header;
  for (const auto& n : kJointNames)
    for (const char* axis : {"_x", "_y", "_z"}) header += "," + std::string(n) + axis;
  return header;
}

// Splits one CSV line into fields (no quoting: our files hold numbers only).
std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

template <typename T>
T parse_number(std::string_view text, const fs::path& path, int line_no, const char* column) {
  while (!text.empty() && (text.back() == '\r' || text.back() == ' ')) text.remove_suffix(1);
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  HULLPOSE_THROW_UNLESS(ec == std::errc() && end == text.data() + text.size(),
                        path.string() << ":" << line_no << ": column " << column << ": '" << text
                                      << "' is not a number");
  if constexpr (std::is_floating_point_v<T>)
    HULLPOSE_THROW_UNLESS(std::isfinite(value), path.string() << ":" << line_no << ": column "
                                                              << column << " is not finite");
  return value;
}

// Shared by ground truth (frame,utime,...) and estimates (frame,valid,reason[,model],...).
// `old_lead_header`, if not empty, is an older layout still accepted (its missing columns
// default).
std::vector<PoseRecord> read_pose_csv(std::istream& in, const fs::path& path,
                                      const std::string& lead_header, bool estimates,
                                      const std::string& old_lead_header = "") {
  std::string line;
  HULLPOSE_THROW_UNLESS(std::getline(in, line), path.string() << ": empty file");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const bool old_layout = !old_lead_header.empty() && line == old_lead_header + joint_columns();
  HULLPOSE_THROW_UNLESS(line == lead_header + joint_columns() || old_layout,
                        path.string()
                            << ":1: header must be '" << lead_header << ",HeadTop_x,...,RToe_z'");
  const size_t lead = split(old_layout ? old_lead_header : lead_header).size();
  std::vector<PoseRecord> records;
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    const auto f = split(line);
    HULLPOSE_THROW_UNLESS(f.size() == lead + 3 * kNumJoints,
                          path.string() << ":" << line_no << ": expected " << lead + 3 * kNumJoints
                                        << " fields, got " << f.size());
    PoseRecord r;
    r.frame = parse_number<int>(f[0], path, line_no, "frame");
    if (estimates) {
      const int valid = parse_number<int>(f[1], path, line_no, "valid");
      HULLPOSE_THROW_UNLESS(valid == 0 || valid == 1,
                            path.string() << ":" << line_no << ": valid must be 0 or 1");
      r.valid = valid == 1;
      r.reason = parse_number<int>(f[2], path, line_no, "reason");
      if (!old_layout) r.model_version = parse_number<int>(f[3], path, line_no, "model");
    } else {
      r.utime = parse_number<int64_t>(f[1], path, line_no, "utime");
    }
    for (int j = 0; j < kNumJoints; ++j)
      for (int a = 0; a < 3; ++a)
        r.joints[static_cast<size_t>(j)][a] =
            parse_number<double>(f[lead + static_cast<size_t>(3 * j + a)], path, line_no,
                                 kJointNames[static_cast<size_t>(j)].data());
    HULLPOSE_THROW_UNLESS(records.empty() || r.frame > records.back().frame,
                          path.string() << ":" << line_no << ": frame " << r.frame
                                        << " is not after frame " << records.back().frame);
    records.push_back(r);
  }
  return records;
}

void write_joints(std::ostream& out, const JointPositions& joints) {
  char buf[32];
  for (const auto& p : joints)
    for (int a = 0; a < 3; ++a) {
      std::snprintf(buf, sizeof buf, ",%.3f", p[a]);
      out << buf;
    }
  out << '\n';
}

}  // namespace

fs::path DatasetPaths::camera_dir(int camera_id) const {
  return root_ / ("cam" + std::to_string(camera_id));
}
fs::path DatasetPaths::mask(int camera_id, int frame) const {
  return camera_dir(camera_id) / frame_name("mask", frame);
}
fs::path DatasetPaths::rgb(int camera_id, int frame) const {
  return camera_dir(camera_id) / frame_name("rgb", frame);
}
fs::path DatasetPaths::background(int camera_id, int index) const {
  return camera_dir(camera_id) / frame_name("background", index);
}

void write_meta(const fs::path& path, const DatasetMeta& m) {
  const nlohmann::ordered_json j = {{"format", DatasetMeta::kFormat},
                                    {"motion", m.motion},
                                    {"frames", m.frames},
                                    {"fps", m.fps},
                                    {"seed", m.seed},
                                    {"start_utime", m.start_utime},
                                    {"stature_mm", m.stature_mm},
                                    {"noise", m.noise},
                                    {"camera_ids", m.camera_ids}};
  std::ofstream out(path);
  HULLPOSE_THROW_UNLESS(out, path.string() << ": cannot write");
  out << j.dump(2) << '\n';
  HULLPOSE_THROW_UNLESS(out, path.string() << ": cannot write");
}

namespace {

// meta.json's fields, each read with its type checked and named in the error.
class MetaReader {
 public:
  MetaReader(const fs::path& path, const nlohmann::json& j) : file_(path.string()), j_(j) {}

  const nlohmann::json& need(const char* key) const {
    const auto it = j_.find(key);
    HULLPOSE_THROW_UNLESS(it != j_.end() && !it->is_null(),
                          file_ << ": missing field '" << key << "'");
    return *it;
  }
  std::string text(const char* key) const {
    const nlohmann::json& v = need(key);
    HULLPOSE_THROW_UNLESS(v.is_string(),
                          file_ << ": field '" << key << "' must be a string, got " << v.dump());
    return v.get<std::string>();
  }
  double number(const char* key) const {
    const nlohmann::json& v = need(key);
    HULLPOSE_THROW_UNLESS(v.is_number() && std::isfinite(v.get<double>()),
                          file_ << ": field '" << key << "' must be a number, got " << v.dump());
    return v.get<double>();
  }
  // Integers; as a string of digits too (datasets written before meta.json had 64-bit numbers).
  template <class T>
  T integer(const char* key) const {
    const nlohmann::json& v = need(key);
    T out{};
    bool ok = false;
    if (v.is_number_integer()) {
      ok = v.is_number_unsigned()
               ? v.get<uint64_t>() <= static_cast<uint64_t>(std::numeric_limits<T>::max())
               : v.get<int64_t>() >= static_cast<int64_t>(std::numeric_limits<T>::min()) &&
                     v.get<int64_t>() <= static_cast<int64_t>(std::numeric_limits<T>::max());
      if (ok) out = v.get<T>();
    } else if (v.is_string()) {
      const std::string& s = v.get_ref<const std::string&>();
      const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
      ok = !s.empty() && ec == std::errc() && end == s.data() + s.size();
    }
    HULLPOSE_THROW_UNLESS(ok, file_ << ": field '" << key << "' must be an integer in ["
                                    << std::numeric_limits<T>::min() << ", "
                                    << std::numeric_limits<T>::max() << "], got " << v.dump());
    return out;
  }
  std::vector<int> integers(const char* key) const {
    const nlohmann::json& v = need(key);
    HULLPOSE_THROW_UNLESS(v.is_array(),
                          file_ << ": field '" << key << "' must be a list of integers");
    std::vector<int> out;
    for (const nlohmann::json& item : v) {
      HULLPOSE_THROW_UNLESS(item.is_number_integer(), file_ << ": field '" << key
                                                            << "' must hold integers, got "
                                                            << item.dump());
      out.push_back(item.get<int>());
    }
    return out;
  }

 private:
  std::string file_;
  const nlohmann::json& j_;
};

}  // namespace

DatasetMeta read_meta(const fs::path& path) {
  HULLPOSE_THROW_UNLESS(fs::exists(path), path.string() << ": not found");
  std::ifstream in(path);
  HULLPOSE_THROW_UNLESS(in, path.string() << ": cannot open");
  std::stringstream text;
  text << in.rdbuf();
  return parse_meta(text.str(), path);
}

DatasetMeta parse_meta(std::string_view text, const fs::path& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    HULLPOSE_THROW(path.string() << ": not valid JSON: " << e.what());
  }
  HULLPOSE_THROW_UNLESS(j.is_object(), path.string() << ": must be a JSON object");
  const MetaReader r(path, j);
  const int format = r.integer<int>("format");
  HULLPOSE_THROW_UNLESS(format == DatasetMeta::kFormat,
                        path.string() << ": unknown dataset format " << format
                                      << " (this build reads " << DatasetMeta::kFormat << ")");
  DatasetMeta m;
  m.motion = r.text("motion");
  m.frames = r.integer<int>("frames");
  m.fps = r.number("fps");
  m.seed = r.integer<uint64_t>("seed");
  m.start_utime = r.integer<int64_t>("start_utime");
  m.stature_mm = r.number("stature_mm");
  m.noise = r.text("noise");
  m.camera_ids = r.integers("camera_ids");
  HULLPOSE_THROW_UNLESS(m.frames >= 0,
                        path.string() << ": field 'frames' must not be negative, got " << m.frames);
  HULLPOSE_THROW_UNLESS(m.fps > 0, path.string()
                                       << ": field 'fps' must be positive, got " << m.fps);
  return m;
}

void write_ground_truth(const fs::path& path, const std::vector<PoseRecord>& frames) {
  std::ofstream out(path);
  HULLPOSE_THROW_UNLESS(out, path.string() << ": cannot write");
  out << "frame,utime" << joint_columns() << '\n';
  for (const auto& r : frames) {
    out << r.frame << ',' << r.utime;
    write_joints(out, r.joints);
  }
  HULLPOSE_THROW_UNLESS(out, path.string() << ": write failed");
}

std::vector<PoseRecord> read_ground_truth(const fs::path& path) {
  std::ifstream in(path);
  HULLPOSE_THROW_UNLESS(in, path.string() << ": cannot open");
  return read_pose_csv(in, path, "frame,utime", false);
}

std::vector<PoseRecord> parse_ground_truth(const std::string& text, const fs::path& path) {
  std::istringstream in(text);
  return read_pose_csv(in, path, "frame,utime", false);
}

EstimateWriter::EstimateWriter(const fs::path& path) : path_(path), out_(path) {
  HULLPOSE_THROW_UNLESS(out_, path.string() << ": cannot write");
  out_ << "frame,valid,reason,model" << joint_columns() << '\n';
}

void EstimateWriter::write(const PoseRecord& r) {
  out_ << r.frame << ',' << (r.valid ? 1 : 0) << ',' << r.reason << ',' << r.model_version;
  write_joints(out_, r.joints);
  HULLPOSE_THROW_UNLESS(out_, path_.string() << ": write failed");
}

std::vector<PoseRecord> read_estimates(const fs::path& path) {
  std::ifstream in(path);
  HULLPOSE_THROW_UNLESS(in, path.string() << ": cannot open");
  return read_pose_csv(in, path, "frame,valid,reason,model", true, "frame,valid,reason");
}

std::vector<PoseRecord> parse_estimates(const std::string& text, const fs::path& path) {
  std::istringstream in(text);
  return read_pose_csv(in, path, "frame,valid,reason,model", true, "frame,valid,reason");
}

}  // namespace hullpose
