#include "hullpose/camera_node/node_config.hpp"

#include <cstdio>
#include <opencv2/core.hpp>

#include "hullpose/auth/rig_key.hpp"
#include "hullpose/common/check.hpp"

namespace hullpose::camera_node {
namespace {

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  std::string where(const std::string& field) const { return file_ + ": " + field; }

  static bool present(const cv::FileNode& n) { return !n.empty() && !n.isNone(); }

  std::string scalar_text(const cv::FileNode& n, const std::string& field) const {
    if (n.isString()) return static_cast<std::string>(n);
    if (n.isInt()) return std::to_string(static_cast<int>(n));
    if (n.isReal()) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(n));
      return buf;
    }
    HULLPOSE_THROW(where(field) << ": must be a scalar (number or text)");
  }

  std::string string(const cv::FileNode& parent, const char* key, const std::string& ctx, bool required,
                     const std::string& fallback = "") const {
    const cv::FileNode n = parent[key];
    const std::string field = ctx.empty() ? key : ctx + "." + key;
    if (!present(n)) {
      HULLPOSE_THROW_UNLESS(!required, where(field) << ": missing (required)");
      return fallback;
    }
    HULLPOSE_THROW_UNLESS(n.isString(), where(field) << ": must be text");
    const std::string s = n;
    HULLPOSE_THROW_UNLESS(!s.empty() || !required, where(field) << ": must not be empty");
    return s;
  }

  int integer(const cv::FileNode& parent, const char* key, const std::string& ctx, bool required, int fallback,
              int min, int max) const {
    const cv::FileNode n = parent[key];
    const std::string field = ctx.empty() ? key : ctx + "." + key;
    if (!present(n)) {
      HULLPOSE_THROW_UNLESS(!required, where(field) << ": missing (required)");
      return fallback;
    }
    HULLPOSE_THROW_UNLESS(n.isInt(), where(field) << ": must be an integer");
    const int v = n;
    HULLPOSE_THROW_UNLESS(v >= min && v <= max,
                          where(field) << ": must be in [" << min << ", " << max << "], got " << v);
    return v;
  }

  cv::FileNode map(const cv::FileNode& parent, const char* key, const std::string& ctx, bool required) const {
    const cv::FileNode n = parent[key];
    const std::string field = ctx.empty() ? key : ctx + "." + key;
    if (!present(n)) {
      HULLPOSE_THROW_UNLESS(!required, where(field) << ": missing (required)");
      return n;
    }
    HULLPOSE_THROW_UNLESS(n.isMap(), where(field) << ": must be a mapping");
    return n;
  }

  // Every key of `node` except those in `skip` becomes a parameter.
  Params params(const cv::FileNode& node, const std::string& ctx, std::initializer_list<const char*> skip) const {
    Params p(where(ctx));
    if (!present(node)) return p;
    for (const std::string& key : node.keys()) {
      bool skipped = false;
      for (const char* s : skip) skipped = skipped || key == s;
      if (!skipped) p.set(key, scalar_text(node[key], ctx + "." + key));
    }
    return p;
  }

  void only_keys(const cv::FileNode& node, const std::string& ctx, std::initializer_list<const char*> allowed) const {
    if (!present(node)) return;
    for (const std::string& key : node.keys()) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || key == a;
      HULLPOSE_THROW_UNLESS(ok, where(ctx.empty() ? key : ctx + "." + key) << ": unknown field");
    }
  }

 private:
  std::string file_;
};

std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p) {
  const std::filesystem::path path(p);
  return path.is_absolute() ? path : base / path;
}

}  // namespace

NodeConfig load_node_config(const std::filesystem::path& file) {
  NodeConfig c;
  c.file = file;
  c.base_dir = std::filesystem::absolute(file).parent_path();
  const std::string name = file.string();
  HULLPOSE_THROW_UNLESS(std::filesystem::is_regular_file(file), name << ": config file not found");
  cv::FileStorage fs;
  try {
    fs.open(name, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    HULLPOSE_THROW(name << ": not valid YAML: " << e.err);
  }
  HULLPOSE_THROW_UNLESS(fs.isOpened(), name << ": cannot be read as YAML");
  const Reader r(name);
  const cv::FileNode root = fs.root();
  HULLPOSE_THROW_UNLESS(root.isMap(), name << ": top level must be a mapping");
  r.only_keys(root, "", {"camera_id", "rig_file", "source", "bgs", "post", "lcm", "trigger"});

  c.camera_id = r.integer(root, "camera_id", "", true, -1, 0, 63);
  c.rig_file = resolve(c.base_dir, r.string(root, "rig_file", "", true));

  const cv::FileNode source = r.map(root, "source", "", true);
  c.source.type = r.string(source, "type", "source", true);
  c.source.params = r.params(source, "source", {"type"});

  const cv::FileNode bgs = r.map(root, "bgs", "", true);
  r.only_keys(bgs, "bgs", {"method", "learn_frames", "background", "params"});
  c.bgs.method = r.string(bgs, "method", "bgs", true);
  c.bgs.learn_frames = r.integer(bgs, "learn_frames", "bgs", false, 30, 1, 100000);
  const std::string background = r.string(bgs, "background", "bgs", false);
  if (!background.empty()) c.bgs.background = resolve(c.base_dir, background).string();
  c.bgs.params = r.params(r.map(bgs, "params", "bgs", false), "bgs.params", {});

  const cv::FileNode post = r.map(root, "post", "", false);
  if (Reader::present(post)) {
    r.only_keys(post, "post", {"open_radius", "close_radius", "min_blob_area", "max_hole_area", "roi"});
    c.post.open_radius = r.integer(post, "open_radius", "post", false, c.post.open_radius, 0, 32);
    c.post.close_radius = r.integer(post, "close_radius", "post", false, c.post.close_radius, 0, 32);
    c.post.min_blob_area = r.integer(post, "min_blob_area", "post", false, c.post.min_blob_area, 0, 1 << 26);
    c.post.max_hole_area = r.integer(post, "max_hole_area", "post", false, c.post.max_hole_area, 0, 1 << 26);
    const cv::FileNode roi = post["roi"];
    if (Reader::present(roi)) {
      HULLPOSE_THROW_UNLESS(roi.isSeq() && roi.size() == 4, r.where("post.roi") << ": must be [x, y, width, height]");
      for (int i = 0; i < 4; ++i)
        HULLPOSE_THROW_UNLESS(roi[i].isInt(), r.where("post.roi") << ": element " << i << " must be an integer");
      c.post.roi = cv::Rect(static_cast<int>(roi[0]), static_cast<int>(roi[1]), static_cast<int>(roi[2]),
                            static_cast<int>(roi[3]));
      HULLPOSE_THROW_UNLESS(c.post.roi.x >= 0 && c.post.roi.y >= 0 && c.post.roi.width > 0 && c.post.roi.height > 0,
                            r.where("post.roi") << ": x, y must be >= 0 and width, height > 0");
    }
  }

  const cv::FileNode lcm = r.map(root, "lcm", "", false);
  if (Reader::present(lcm)) {
    r.only_keys(lcm, "lcm", {"url", "rig_key", "silhouette_channel", "status_channel", "queue_depth", "status_period_ms"});
    c.lcm.url = r.string(lcm, "url", "lcm", false, c.lcm.url);
    const std::string key = r.string(lcm, "rig_key", "lcm", false, "");
    if (!key.empty()) {
      c.lcm.rig_key = resolve(c.base_dir, key);
      try {
        (void)auth::RigKey::load(c.lcm.rig_key.string());  // checked with the rest, before anything opens
      } catch (const Error& e) {
        HULLPOSE_THROW(r.where("lcm.rig_key") << ": " << e.what());
      }
    }
    c.lcm.silhouette_channel = r.string(lcm, "silhouette_channel", "lcm", false, c.lcm.silhouette_channel);
    c.lcm.status_channel = r.string(lcm, "status_channel", "lcm", false, c.lcm.status_channel);
    c.lcm.queue_depth = r.integer(lcm, "queue_depth", "lcm", false, c.lcm.queue_depth, 1, 1024);
    c.lcm.status_period_ms = r.integer(lcm, "status_period_ms", "lcm", false, c.lcm.status_period_ms, 10, 600000);
  }

  const cv::FileNode trigger = r.map(root, "trigger", "", false);
  if (Reader::present(trigger)) {
    TriggerConfig& t = c.trigger;
    t.enabled = true;
    r.only_keys(trigger, "trigger", {"edges", "chip", "line", "path", "camera", "channel", "max_residual_us", "wait_ms",
                                     "connect_timeout_ms", "clock_offset_ms", "clock_step_ms", "clock_step_after"});
    const std::string edges = r.string(trigger, "edges", "trigger", true);
    const auto only_for = [&](const char* key, const char* kind) {
      HULLPOSE_THROW_UNLESS(!Reader::present(trigger[key]),
                            r.where(std::string("trigger.") + key) << ": only for edges: " << kind);
    };
    if (edges == "gpiod") {
      const std::string chip = r.string(trigger, "chip", "trigger", true);
      const int line = r.integer(trigger, "line", "trigger", true, 0, 0, 65535);
      only_for("path", "wire");
      HULLPOSE_THROW_UNLESS(chip.find(':') == std::string::npos, r.where("trigger.chip") << ": '" << chip
                                                                                           << "' must not contain ':'");
      t.edges = "gpiod:" + chip + ":" + std::to_string(line);
    } else if (edges == "wire") {
      t.edges = "wire:" + resolve(c.base_dir, r.string(trigger, "path", "trigger", true)).string();
      only_for("chip", "gpiod");
      only_for("line", "gpiod");
    } else {
      HULLPOSE_THROW(r.where("trigger.edges") << ": unknown trigger input '" << edges
                                              << "' (gpiod: the trigger GPIO; wire: a simulated rig's wire)");
    }
    const std::string camera = r.string(trigger, "camera", "trigger", false, "triggered");
    HULLPOSE_THROW_UNLESS(camera == "triggered" || camera == "free_running",
                          r.where("trigger.camera") << ": '" << camera << "' is not triggered or free_running");
    t.free_running = camera == "free_running";
    t.channel = r.string(trigger, "channel", "trigger", false, t.channel);
    t.max_residual_us = r.integer(trigger, "max_residual_us", "trigger", false, t.max_residual_us, 1, 1'000'000);
    t.wait_ms = r.integer(trigger, "wait_ms", "trigger", false, t.wait_ms, 0, 10'000);
    t.connect_timeout_ms = r.integer(trigger, "connect_timeout_ms", "trigger", false, t.connect_timeout_ms, 0, 600'000);
    t.clock_offset_ms = r.integer(trigger, "clock_offset_ms", "trigger", false, 0, -3'600'000, 3'600'000);
    t.clock_step_ms = r.integer(trigger, "clock_step_ms", "trigger", false, 0, -3'600'000, 3'600'000);
    t.clock_step_after = r.integer(trigger, "clock_step_after", "trigger", false, 0, 0, 1 << 30);
  }
  return c;
}

}  // namespace hullpose::camera_node
