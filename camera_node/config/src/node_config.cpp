#include "hullpose/camera_node/node_config.hpp"

#include <optional>

#include "hullpose/auth/rig_key.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/yaml.hpp"

namespace hullpose::camera_node {
namespace {

// Every key of `node` except those in `skip` becomes a stage parameter, its scalar text as written.
Params params(const std::optional<yaml::Node>& node, const std::string& scope,
              std::initializer_list<const char*> skip) {
  Params p(scope);
  if (!node) return p;
  HULLPOSE_THROW_UNLESS(node->is_map(), node->where() << ": must be a mapping");
  for (const std::string& key : node->keys()) {
    bool skipped = false;
    for (const char* s : skip) skipped = skipped || key == s;
    if (!skipped) p.set(key, node->need(key).text());
  }
  return p;
}

std::optional<yaml::Node> map(const yaml::Node& parent, const std::string& key, bool required) {
  std::optional<yaml::Node> n =
      required ? std::optional<yaml::Node>(parent.need(key)) : parent.get(key);
  HULLPOSE_THROW_UNLESS(!n || n->is_map(), n->where() << ": must be a mapping");
  return n;
}

std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p) {
  const std::filesystem::path path(p);
  return path.is_absolute() ? path : base / path;
}

void read_post(const yaml::Node& post, PostConfig& c) {
  c.open_radius = post.integer_or("open_radius", c.open_radius, 0, 32);
  c.close_radius = post.integer_or("close_radius", c.close_radius, 0, 32);
  c.min_blob_area = post.integer_or("min_blob_area", c.min_blob_area, 0, 1 << 26);
  c.max_hole_area = post.integer_or("max_hole_area", c.max_hole_area, 0, 1 << 26);
  if (const std::optional<yaml::Node> roi = post.get("roi")) {
    HULLPOSE_THROW_UNLESS(roi->is_list() && roi->size() == 4,
                          roi->where() << ": must be [x, y, width, height]");
    const std::vector<yaml::Node> v = roi->items();
    c.roi = cv::Rect(v[0].integer(), v[1].integer(), v[2].integer(), v[3].integer());
    HULLPOSE_THROW_UNLESS(c.roi.x >= 0 && c.roi.y >= 0 && c.roi.width > 0 && c.roi.height > 0,
                          roi->where() << ": x, y must be >= 0 and width, height > 0");
  }
}

void read_lcm(const yaml::Node& lcm, const std::filesystem::path& base_dir, LcmConfig& c) {
  c.url = lcm.string_or("url", c.url);
  if (const std::optional<yaml::Node> key = lcm.get("rig_key")) {
    c.rig_key = resolve(base_dir, key->string());
    try {
      (void)auth::RigKey::load(c.rig_key.string());  // checked with the rest, before anything opens
    } catch (const Error& e) {
      HULLPOSE_THROW(key->where() << ": " << e.what());
    }
  }
  c.silhouette_channel = lcm.string_or("silhouette_channel", c.silhouette_channel);
  c.status_channel = lcm.string_or("status_channel", c.status_channel);
  c.queue_depth = lcm.integer_or("queue_depth", c.queue_depth, 1, 1024);
  c.status_period_ms = lcm.integer_or("status_period_ms", c.status_period_ms, 10, 600000);
}

void read_trigger(const yaml::Node& trigger, const std::filesystem::path& base_dir,
                  TriggerConfig& t) {
  t.enabled = true;
  const yaml::Node edges_node = trigger.need("edges");
  const std::string edges = edges_node.string();
  const auto only_for = [&](const char* key, const char* kind) {
    const std::optional<yaml::Node> n = trigger.get(key);
    HULLPOSE_THROW_UNLESS(!n, n->where() << ": only for edges: " << kind);
  };
  if (edges == "gpiod") {
    const yaml::Node chip_node = trigger.need("chip");
    const std::string chip = chip_node.string();
    const int line = static_cast<int>(trigger.need("line").integer(0, 65535));
    only_for("path", "wire");
    HULLPOSE_THROW_UNLESS(chip.find(':') == std::string::npos,
                          chip_node.where() << ": '" << chip << "' must not contain ':'");
    t.edges = "gpiod:" + chip + ":" + std::to_string(line);
  } else if (edges == "wire") {
    t.edges = "wire:" + resolve(base_dir, trigger.need("path").string()).string();
    only_for("chip", "gpiod");
    only_for("line", "gpiod");
  } else {
    HULLPOSE_THROW(edges_node.where()
                   << ": unknown trigger input '" << edges
                   << "' (gpiod: the trigger GPIO; wire: a simulated rig's wire)");
  }
  const std::optional<yaml::Node> camera_node = trigger.get("camera");
  const std::string camera = camera_node ? camera_node->string() : "triggered";
  HULLPOSE_THROW_UNLESS(camera == "triggered" || camera == "free_running",
                        camera_node->where()
                            << ": '" << camera << "' is not triggered or free_running");
  t.free_running = camera == "free_running";
  t.channel = trigger.string_or("channel", t.channel);
  t.max_residual_us = trigger.integer_or("max_residual_us", t.max_residual_us, 1, 1'000'000);
  t.wait_ms = trigger.integer_or("wait_ms", t.wait_ms, 0, 10'000);
  t.connect_timeout_ms = trigger.integer_or("connect_timeout_ms", t.connect_timeout_ms, 0, 600'000);
  t.clock_offset_ms = trigger.integer_or("clock_offset_ms", 0, -3'600'000, 3'600'000);
  t.clock_step_ms = trigger.integer_or("clock_step_ms", 0, -3'600'000, 3'600'000);
  t.clock_step_after = trigger.integer_or("clock_step_after", 0, 0, 1 << 30);
}

NodeConfig read_node_config(const yaml::Document& doc, const std::filesystem::path& file) {
  NodeConfig c;
  c.file = file;
  c.base_dir = std::filesystem::absolute(file).parent_path();
  const std::string name = file.string();
  const yaml::Node root = doc.root();

  c.camera_id = static_cast<int>(root.need("camera_id").integer(0, 63));
  c.rig_file = resolve(c.base_dir, root.need("rig_file").string());

  const yaml::Node source = *map(root, "source", true);
  c.source.type = source.need("type").string();
  c.source.params = params(source, name + ": source", {"type"});
  source.mark_all_read();  // the source checks its own parameters (Params::expect_all_used)

  const yaml::Node bgs = *map(root, "bgs", true);
  c.bgs.method = bgs.need("method").string();
  c.bgs.learn_frames = bgs.integer_or("learn_frames", 30, 1, 100000);
  const std::string background = bgs.string_or("background", "");
  if (!background.empty()) c.bgs.background = resolve(c.base_dir, background).string();
  const std::optional<yaml::Node> bgs_params = map(bgs, "params", false);
  c.bgs.params = params(bgs_params, name + ": bgs.params", {});
  if (bgs_params) bgs_params->mark_all_read();

  if (const std::optional<yaml::Node> post = map(root, "post", false)) read_post(*post, c.post);
  if (const std::optional<yaml::Node> lcm = map(root, "lcm", false))
    read_lcm(*lcm, c.base_dir, c.lcm);
  if (const std::optional<yaml::Node> trigger = map(root, "trigger", false))
    read_trigger(*trigger, c.base_dir, c.trigger);
  doc.check_all_read();
  return c;
}

}  // namespace

NodeConfig load_node_config(const std::filesystem::path& file) {
  HULLPOSE_THROW_UNLESS(std::filesystem::is_regular_file(file), file.string()
                                                                    << ": config file not found");
  return read_node_config(yaml::Document::load(file), file);
}

NodeConfig parse_node_config(const std::string& text, const std::filesystem::path& file) {
  return read_node_config(yaml::Document::parse(text, file.string()), file);
}

}  // namespace hullpose::camera_node
