#include "hullpose/skeleton_io/take.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>

#include "hullpose/auth/message_auth.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/msg/wire.hpp"

namespace hullpose::skeleton_io {
namespace {

constexpr unsigned char kLogSync[4] = {0xED, 0xA1, 0xDA, 0x01};  // lcm-logger's event sync word

bool is_lcm_log(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  HULLPOSE_THROW_UNLESS(in.good(), path.string() << ": cannot read");
  unsigned char head[4] = {};
  in.read(reinterpret_cast<char*>(head), 4);
  return in.gcount() == 4 && std::memcmp(head, kLogSync, 4) == 0;
}

Take read_log(const std::filesystem::path& path, double fps, const std::string& channel) {
  lcm::LogFile log(path.string(), "r");
  HULLPOSE_THROW_UNLESS(log.good(), path.string() << ": cannot open as an lcm-logger log");
  Take take;
  std::map<int64_t, SkeletonFrame>
      by_seq;  // a log may hold a sequence twice (republished): last wins
  hullpose_msg::skeleton_t msg;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != channel) continue;
    SkeletonFrame f;
    // A keyed rig's log holds each message with its MAC trailer (docs/messages.md); a recorded
    // take is read without the key, as an open receiver reads it.
    if (e->datalen < 0 ||
        !wire::decode(
            std::span<const uint8_t>(static_cast<const uint8_t*>(e->data),
                                     auth::strip_trailer(e->data, static_cast<size_t>(e->datalen))),
            msg) ||
        !from_message(msg, f)) {
      ++take.malformed;
      continue;
    }
    by_seq[f.seq] = f;
  }
  HULLPOSE_THROW_UNLESS(!by_seq.empty(),
                        path.string() << ": no skeleton_t message on channel '" << channel << "'");
  std::vector<int64_t> steps;
  for (auto it = by_seq.begin(), next = std::next(it); next != by_seq.end(); ++it, ++next)
    if (next->first == it->first + 1 && next->second.utime > it->second.utime)
      steps.push_back(next->second.utime - it->second.utime);
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2),
                     steps.end());
    take.fps = 1e6 / static_cast<double>(steps[steps.size() / 2]);
  } else {
    take.fps = fps;
  }
  const int64_t first = by_seq.begin()->first, last = by_seq.rbegin()->first;
  HULLPOSE_THROW_UNLESS(last - first < 10'000'000,
                        path.string() << ": trigger sequences " << first << ".." << last
                                      << " span more than 10 million frames");
  take.frames.reserve(static_cast<size_t>(last - first + 1));
  for (int64_t s = first; s <= last; ++s) {
    auto it = by_seq.find(s);
    if (it != by_seq.end()) {
      take.frames.push_back(it->second);
      continue;
    }
    SkeletonFrame missing;
    missing.seq = s;
    missing.reason = hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS;
    missing.utime = by_seq.begin()->second.utime +
                    static_cast<int64_t>(static_cast<double>(s - first) * 1e6 / take.fps);
    take.frames.push_back(missing);
    ++take.inserted;
  }
  return take;
}

Take read_csv(const std::filesystem::path& path, double fps) {
  HULLPOSE_THROW_UNLESS(fps > 0 && fps <= 10'000,
                        path.string() << ": frame rate must be in (0, 10000], got " << fps);
  const std::vector<PoseRecord> records = read_estimates(path);
  HULLPOSE_THROW_UNLESS(!records.empty(), path.string() << ": no frames");
  Take take;
  take.fps = fps;
  const int first = records.front().frame;
  int expect = first;
  for (const PoseRecord& r : records) {
    HULLPOSE_THROW_UNLESS(r.frame >= expect, path.string()
                                                 << ": frame " << r.frame << " out of order (after "
                                                 << expect - 1 << ")");
    for (; expect < r.frame; ++expect) {
      SkeletonFrame missing;
      missing.seq = expect;
      missing.reason = hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS;
      take.frames.push_back(missing);
      ++take.inserted;
    }
    SkeletonFrame f;
    f.seq = r.frame;
    f.valid = r.valid;
    f.reason = r.reason;
    f.joints = r.joints;
    f.model_version = r.model_version;
    f.confidence.fill(r.valid ? 1.f : 0.f);  // an estimate file keeps no confidence
    take.frames.push_back(f);
    expect = r.frame + 1;
  }
  return take;
}

}  // namespace

bool from_message(const hullpose_msg::skeleton_t& msg, SkeletonFrame& out) {
  if (msg.num_joints != kNumJoints || msg.position.size() != kNumJoints ||
      msg.confidence.size() != kNumJoints || msg.model_version < 0)
    return false;
  for (const auto& p : msg.position)
    if (p.size() != 3 || !std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      return false;
  out.utime = msg.utime;
  out.seq = msg.trigger_seq;
  out.valid = msg.valid;
  out.reason = msg.reason;
  for (size_t j = 0; j < kNumJoints; ++j) {
    const auto& p = msg.position[j];
    out.joints[j] = Eigen::Vector3d(p[0], p[1], p[2]);
    out.confidence[j] = msg.confidence[j];
  }
  out.cameras_used_mask = msg.cameras_used_mask;
  out.num_cameras_used = msg.num_cameras_used;
  out.published_us = msg.published_us;
  out.model_version = msg.model_version;
  return true;
}

void to_message(const SkeletonFrame& f, const std::string& rig_id, hullpose_msg::skeleton_t& m) {
  m.utime = f.utime;
  m.rig_id = rig_id;
  m.trigger_seq = f.seq;
  m.subject_id = 0;
  m.num_joints = kNumJoints;
  m.joint_name.assign(kJointNames.begin(), kJointNames.end());
  m.position.assign(kNumJoints, std::vector<float>(3));
  m.confidence.resize(kNumJoints);
  for (size_t j = 0; j < kNumJoints; ++j) {
    for (int k = 0; k < 3; ++k)
      m.position[j][static_cast<size_t>(k)] = static_cast<float>(f.joints[j][k]);
    m.confidence[j] = f.confidence[j];
  }
  m.valid = f.valid;
  m.reason = static_cast<int8_t>(f.reason);
  m.cameras_used_mask = f.cameras_used_mask;
  m.num_cameras_used = f.num_cameras_used;
  m.capture_us = m.node_done_us = m.received_us = m.fused_us = 0;
  m.published_us = f.published_us;
  m.model_version = f.model_version;
}

Take read_take(const std::filesystem::path& path, double fps, const std::string& channel) {
  return is_lcm_log(path) ? read_log(path, fps, channel) : read_csv(path, fps);
}

}  // namespace hullpose::skeleton_io
