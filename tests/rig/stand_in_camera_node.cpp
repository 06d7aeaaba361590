// A stand-in camera node for the system tests until camera_node/app lands: the real trigger
// stage (wire edge source, sequence mapper, frame matcher) and a simulated triggered sensor
// whose frames are masks carrying their own sequence (seq_pattern.hpp), published as real
// silhouette_t over LCM. --clock-offset-ms puts the board's clock off; --hostile also sends
// garbage and hostile messages on SILHOUETTE after every frame; --free-running-fps F makes the
// sensor ignore the trigger and run at its own rate and phase (the frame nearest each edge is
// used, and its residual reported); --masks DIR replays a dataset's masks (DIR/cam<ID>/
// mask_<FFFFFF>.png, docs/conventions.md) instead, frame = trigger_seq modulo the frame count, all
// encoded once at start; --ready-file FILE is written once loaded, before waiting for the wire.
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <csignal>
#include <cstdio>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <random>

#include <hullpose_msg/node_status_t.hpp>
#include <hullpose_msg/silhouette_t.hpp>

#include "hullpose/camera_node/trigger_listener.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/lcm_wire.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/rig.hpp"
#include "hullpose/common/silhouette_codec.hpp"
#include "hullpose/common/time.hpp"
#include "seq_pattern.hpp"

using namespace hullpose;

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// The simulated sensor: exposes a frame 200 us after every edge the trigger input reports.
class TriggeredSensor final : public trigger::EdgeSource {
 public:
  TriggeredSensor(trigger::EdgeSource& inner, std::function<void(int64_t)> exposed) : inner_(inner), exposed_(std::move(exposed)) {}
  int fd() const override { return inner_.fd(); }
  bool read(int64_t& edge_us) override {
    if (!inner_.read(edge_us)) return false;
    exposed_(edge_us + 200);
    return true;
  }
  std::string describe() const override { return inner_.describe(); }

 private:
  trigger::EdgeSource& inner_;
  std::function<void(int64_t)> exposed_;
};

struct Node {
  const Rig& rig;
  const CameraModel& cam;
  trigger::NodeClock clock;
  trigger::TriggerListener* listener = nullptr;
  hullpose_msg::trigger_t trig;
  int64_t announcements = 0, malformed = 0;
  void on_trigger(const lcm::ReceiveBuffer* rb, const std::string&) {
    if (!wire::trigger_ok(rb->data, rb->data_size) ||
        trig.decode(rb->data, 0, static_cast<int>(rb->data_size)) != static_cast<int>(rb->data_size)) {
      ++malformed;
      return;
    }
    ++announcements;
    listener->on_announcement(trig, clock.now_us());
  }
};

void publish_hostile(lcm::LCM& bus, const std::vector<uint8_t>& valid, std::mt19937& rng) {
  std::vector<uint8_t> b(rng() % 300);
  for (auto& x : b) x = static_cast<uint8_t>(rng());
  bus.publish("SILHOUETTE", b.data(), static_cast<unsigned>(b.size()));
  b.assign(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(rng() % valid.size()));
  bus.publish("SILHOUETTE", b.data(), static_cast<unsigned>(b.size()));
  b = valid;
  for (int k = 0; k < 4; ++k) b[16 + static_cast<size_t>(k)] = 0xFF;  // rig_id length -1
  bus.publish("SILHOUETTE", b.data(), static_cast<unsigned>(b.size()));
  b = valid;
  b[rng() % b.size()] ^= static_cast<uint8_t>(1 + rng() % 255);
  bus.publish("SILHOUETTE", b.data(), static_cast<unsigned>(b.size()));
}
}  // namespace

int main(int argc, char** argv) {
  try {
    if (const char* spec = std::getenv("HULLPOSE_LOG")) log::set_levels(spec);
    std::string rig_file, edges = "wire:/tmp/hullpose-wire.sock", lcm_url;
    int camera_id = 0;
    double offset_ms = 0, duration_s = 0, free_fps = 0;
    bool hostile = false;
    std::string masks_dir, ready_file;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      HULLPOSE_THROW_UNLESS(a == "--hostile" || i + 1 < argc, "option " << a << " needs a value");
      if (a == "--rig") rig_file = argv[++i];
      else if (a == "--camera-id") camera_id = std::stoi(argv[++i]);
      else if (a == "--edges") edges = argv[++i];
      else if (a == "--lcm-url") lcm_url = argv[++i];
      else if (a == "--clock-offset-ms") offset_ms = std::stod(argv[++i]);
      else if (a == "--duration-s") duration_s = std::stod(argv[++i]);
      else if (a == "--hostile") hostile = true;
      else if (a == "--masks") masks_dir = argv[++i];
      else if (a == "--ready-file") ready_file = argv[++i];
      else if (a == "--free-running-fps") free_fps = std::stod(argv[++i]);
      else HULLPOSE_THROW("unknown option '" << a << "'");
    }
    const Rig rig = load_rig(rig_file);
    const CameraModel* cam = rig.find(camera_id);
    HULLPOSE_THROW_UNLESS(cam, rig_file << ": no camera " << camera_id);
    lcm::LCM bus(lcm_url);
    HULLPOSE_THROW_UNLESS(bus.good(), "LCM '" << lcm_url << "' cannot be opened");

    // Dataset masks, encoded once: per frame only the payload is sent.
    std::vector<std::vector<uint8_t>> replay;
    std::vector<PixelRoi> replay_roi;
    if (!masks_dir.empty()) {
      SilhouetteEncoder enc;
      for (int f = 0;; ++f) {
        char name[64];
        std::snprintf(name, sizeof(name), "/cam%d/mask_%06d.png", camera_id, f);
        const std::string path = masks_dir + name;
        if (!std::filesystem::exists(path)) break;
        const cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
        HULLPOSE_THROW_UNLESS(!m.empty() && m.cols == cam->width && m.rows == cam->height,
                              path << ": not a " << cam->width << "x" << cam->height << " mask of camera " << camera_id);
        replay.emplace_back();
        replay_roi.push_back(enc.encode(m, replay.back()));
      }
      HULLPOSE_THROW_UNLESS(!replay.empty(), masks_dir << ": no masks of camera " << camera_id);
    }
    if (!ready_file.empty()) std::ofstream(ready_file) << "ready\n";

    Node node{rig, *cam, {static_cast<int64_t>(offset_ms * 1000)}, nullptr, {}};
    auto wire_edges = trigger::open_edge_source(edges, node.clock, 60'000);
    int64_t frame_id = 0;
    trigger::TriggerListener* listener_ptr = nullptr;
    TriggeredSensor sensor(*wire_edges, [&](int64_t t) {
      if (free_fps <= 0) listener_ptr->on_frame(frame_id++, t);
    });
    trigger::ListenerConfig cfg;
    cfg.rig_id = rig.rig_id;
    const int64_t frame_interval_us = free_fps > 0 ? static_cast<int64_t>(1e6 / free_fps) : 0;
    cfg.matcher.max_residual_us = free_fps > 0 ? frame_interval_us / 2 + 1 : 10'000;
    int64_t next_free_frame = node.clock.now_us() + 12'345;  // its own phase
    int64_t residual_sum = 0, residual_max = 0;
    trigger::TriggerListener listener(cfg, sensor);
    listener_ptr = &listener;
    node.listener = &listener;
    bus.subscribe("TRIGGER", &Node::on_trigger, &node);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);

    cv::Mat mask(cam->height, cam->width, CV_8UC1);
    SilhouetteEncoder encoder;
    hullpose_msg::silhouette_t msg{};
    msg.rig_id = rig.rig_id;
    msg.camera_id = camera_id;
    msg.width = cam->width;
    msg.height = cam->height;
    msg.encoding = hullpose_msg::silhouette_t::ENCODING_RLE_V1;
    std::vector<uint8_t> buf(static_cast<size_t>(cam->width) * cam->height + 1024);
    std::vector<trigger::TaggedFrame> tagged;
    tagged.reserve(64);
    std::mt19937 rng(static_cast<uint32_t>(1000 + camera_id));
    int64_t published = 0, last_seq = -1;
    const int64_t end = duration_s > 0 ? monotonic_us() + static_cast<int64_t>(duration_s * 1e6) : INT64_MAX;
    int64_t next_status = monotonic_us() + 1'000'000;
    while (!g_stop && monotonic_us() < end) {
      pollfd p[2] = {{bus.getFileno(), POLLIN, 0}, {sensor.fd(), POLLIN, 0}};
      int timeout_ms = 5;
      if (free_fps > 0)
        timeout_ms = static_cast<int>(std::clamp<int64_t>((next_free_frame - node.clock.now_us()) / 1000, 0, 5));
      const int n = ::poll(p, sensor.fd() >= 0 ? 2 : 1, timeout_ms);
      for (; free_fps > 0 && node.clock.now_us() >= next_free_frame; next_free_frame += frame_interval_us)
        listener.on_frame(frame_id++, next_free_frame);
      if (n > 0 && (p[0].revents & POLLIN)) bus.handle();
      tagged.clear();
      listener.poll(node.clock.now_us(), tagged);
      for (const trigger::TaggedFrame& f : tagged) {
        const StageTimer t;
        PixelRoi roi;
        if (replay.empty()) {
          testing::draw_seq_mask(mask, f.edge.seq, camera_id);
          roi = encoder.encode(mask, msg.payload);
        } else {
          const auto frame = static_cast<size_t>(f.edge.seq) % replay.size();
          msg.payload.assign(replay[frame].begin(), replay[frame].end());  // capacity reused
          roi = replay_roi[frame];
        }
        msg.utime = f.edge.utime;
        msg.trigger_seq = f.edge.seq;
        msg.capture_utime = f.capture_utime();
        msg.roi_x = roi.x;
        msg.roi_y = roi.y;
        msg.roi_width = roi.width;
        msg.roi_height = roi.height;
        msg.payload_size = static_cast<int32_t>(msg.payload.size());
        msg.encode_us = static_cast<int32_t>(t.elapsed_us());
        msg.node_done_utime = node.clock.now_us() - f.edge.offset_us;
        const int len = msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
        HULLPOSE_ASSERT(len > 0);
        bus.publish("SILHOUETTE", buf.data(), static_cast<unsigned>(len));
        if (hostile) publish_hostile(bus, {buf.begin(), buf.begin() + len}, rng);
        ++published;
        last_seq = f.edge.seq;
        residual_sum += std::llabs(f.residual_us);
        residual_max = std::max<int64_t>(residual_max, std::llabs(f.residual_us));
      }
      if (monotonic_us() >= next_status) {
        next_status += 1'000'000;
        hullpose_msg::node_status_t s{};
        s.utime = realtime_utime();
        s.rig_id = rig.rig_id;
        s.role = "camera_node";
        s.node_id = camera_id;
        s.state = listener.mapper().synced() ? hullpose_msg::node_status_t::STATE_RUNNING : hullpose_msg::node_status_t::STATE_STARTING;
        s.message = "offset node-master " + std::to_string(listener.mapper().offset_us()) + " us, frame residual mean " +
                    std::to_string(published ? residual_sum / published : 0) + " us max " + std::to_string(residual_max) + " us";
        s.frames_total = published;
        s.last_trigger_seq = last_seq;
        for (const Counters* c : {&listener.mapper().counters(), &listener.matcher().counters()})
          for (const auto& [name, value] : c->snapshot()) {
            s.counter_name.push_back(name);
            s.counter_value.push_back(value);
          }
        s.num_counters = static_cast<int32_t>(s.counter_name.size());
        bus.publish("STATUS", &s);
      }
    }
    std::fprintf(stderr, "stand-in camera %d: %lld frames published, offset %lld us, %lld announcements, |residual| mean %lld us max %lld us;",
                 camera_id, static_cast<long long>(published), static_cast<long long>(listener.mapper().offset_us()),
                 static_cast<long long>(node.announcements), static_cast<long long>(published ? residual_sum / published : 0),
                 static_cast<long long>(residual_max));
    for (const Counters* c : {&listener.mapper().counters(), &listener.matcher().counters()})
      for (const auto& [name, value] : c->snapshot()) std::fprintf(stderr, " %s=%lld", name.c_str(), static_cast<long long>(value));
    std::fprintf(stderr, "\n");
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "stand-in camera node: error: %s\n", e.what());
    return 2;
  }
}
