// consumers_sim_rig: a simulated rig for the consumer tests and the bench, over real LCM. It
// publishes SKELETON at --rate from a hullpose-synth motion (every --invalid-every'th frame
// invalid, confidence falling towards the extremities), a STATUS per camera node (fps, drop
// counters, trigger residuals) and one for the fusion host each second, and writes the rig
// file (thesis8) for hullpose-web. With --hull-rate HZ it also publishes a hull on HULL through
// the fusion host's own HullPublisher (fusion_host/service): capsules around the bones carved
// into the 128³ grid of the rig's volume, coarsened and encoded as the host does; with
// --hostile-hulls each is followed by hostile copies (bad size, geometry, count, payload, and
// one cut short) that a view must count and drop. Starts
// publishing once --wait-file exists (if given).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <hullpose_msg/node_status_t.hpp>
#include <limits>
#include <thread>

#include "hullpose/common/bus.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/common/cli.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/common/tool.hpp"
#include "hullpose/common/voxel_grid.hpp"
#include "hullpose/fusion_host/hull_publisher.hpp"
#include "hullpose/msg/wire.hpp"
#include "hullpose/skeleton_io/take.hpp"
#include "hullpose/synth/motion.hpp"
#include "hullpose/synth/rig_gen.hpp"
#include "skeleton_pacer.hpp"

namespace {
// The body as a carved hull would show it: every voxel within `radius_mm` of a bone.
void carve_capsules(const hullpose::JointPositions& joints, const hullpose::VoxelGridSpec& spec,
                    double radius_mm, hullpose::fusion::BitGrid& hull) {
  hull.reset(spec.dims);
  for (const hullpose::Bone& b : hullpose::kBones) {
    const Eigen::Vector3d a = joints[static_cast<size_t>(hullpose::index(b.parent))];
    const Eigen::Vector3d c = joints[static_cast<size_t>(hullpose::index(b.child))];
    const Eigen::Vector3d lo = a.cwiseMin(c).array() - radius_mm,
                          hi = a.cwiseMax(c).array() + radius_mm;
    const Eigen::Vector3i v0 = ((lo - spec.origin_mm) / spec.voxel_mm).cast<int>().cwiseMax(0);
    const Eigen::Vector3i v1 = ((hi - spec.origin_mm) / spec.voxel_mm)
                                   .cast<int>()
                                   .cwiseMin(spec.dims - Eigen::Vector3i::Ones());
    const Eigen::Vector3d ab = c - a;
    const double len2 = std::max(ab.squaredNorm(), 1e-9);
    for (int z = v0.z(); z <= v1.z(); ++z)
      for (int y = v0.y(); y <= v1.y(); ++y)
        for (int x = v0.x(); x <= v1.x(); ++x) {
          const Eigen::Vector3d p = spec.centre_mm({x, y, z});
          const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
          if ((p - (a + t * ab)).norm() <= radius_mm) hull.set(x, y, z);
        }
  }
}
}  // namespace

int run(int argc, const char* const* argv) {
  std::string url, motion = "walk", rig_out, wait_file;
  bool hostile_hulls = false;
  double rate = 30, hull_rate = 0;
  long long count = 90, invalid_every = 10;
  hullpose::cli::CommandLine cl(
      "usage: consumers_sim_rig --lcm-url URL [--motion walk] [--rate 30] [--count 90] "
      "[--invalid-every 10] [--rig-out FILE] [--wait-file FILE] [--hull-rate HZ "
      "[--hostile-hulls]]\n");
  cl.option("--lcm-url", url)
      .option("--motion", motion)
      .option("--rate", rate)
      .option("--count", count)
      .option("--invalid-every", invalid_every)
      .option("--rig-out", rig_out)
      .option("--wait-file", wait_file)
      .option("--hull-rate", hull_rate)
      .flag("--hostile-hulls", hostile_hulls);
  if (!cl.parse(argc, argv)) return 0;
  const hullpose::Rig rig = hullpose::synth::rig_from_name_or_file("thesis8");
  if (!rig_out.empty()) hullpose::save_rig(rig, rig_out);
  const auto bus = hullpose::bus::open_bus(url);
  hullpose::Counters counters;
  std::unique_ptr<hullpose::fusion::HullPublisher> hull_publisher;
  const hullpose::VoxelGridSpec hull_grid = hullpose::VoxelGridSpec::fit(rig.volume, 128);
  hullpose::fusion::BitGrid hull;
  long long hull_every = 0;
  hullpose::msg::CoarseHull coarse;
  std::vector<uint64_t> coarse_scratch;
  hullpose::SilhouetteEncoder encoder;
  hullpose_msg::hull_t bad;
  if (hull_rate > 0) {
    hullpose::fusion::HullPublishOptions ho;
    ho.rate_hz = hull_rate;
    hull_publisher =
        std::make_unique<hullpose::fusion::HullPublisher>(*bus, rig.rig_id, ho, counters);
    hull_every = std::max(1LL, std::llround(rate / hull_rate));
  }
  std::vector<uint8_t> scratch;
  hullpose::synth::MotionOptions mo;
  mo.centre_mm = 0.5 * (rig.volume.min_mm + rig.volume.max_mm);
  mo.centre_mm.z() = 0;
  const auto m = hullpose::synth::make_motion(motion, mo);
  while (!wait_file.empty() && !std::filesystem::exists(wait_file))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));

  hullpose::skeleton_io::SkeletonFrame f;
  hullpose::consumers_test::SkeletonPacer pacer(*bus, rig.rig_id, rate);
  for (long long k = 0; k < count; ++k) {
    m->sample(static_cast<double>(k) / 30.0, f.joints);
    f.valid = invalid_every <= 0 || (k + 1) % invalid_every != 0;
    f.reason = f.valid ? 0 : hullpose_msg::skeleton_t::REASON_TOO_FEW_CAMERAS;
    for (size_t j = 0; j < hullpose::kNumJoints; ++j)
      f.confidence[j] = j == 8 || j == 9 ? 0.4f : 1.f;  // hands less sure
    f.num_cameras_used = f.valid ? 8 : 3;
    f.cameras_used_mask = f.valid ? 0xFF : 0x07;
    f.published_us = 42'000 + static_cast<int32_t>(k % 7) * 1000;
    pacer.publish(k, f);  // stamps f.seq and f.utime (the trigger clock)
    if (hull_publisher && f.valid && k % hull_every == 0) {
      carve_capsules(f.joints, hull_grid, 90, hull);
      hull_publisher->offer(hull, hull_grid, f.utime, f.seq);
      if (hostile_hulls)
        hullpose::fusion::coarsen_hull(hull, hull_grid, 64, coarse, coarse_scratch);
      for (int kind = 0; hostile_hulls && kind < 5; ++kind) {
        hullpose::msg::to_message(coarse, rig.rig_id, encoder, bad);
        bool send = true;
        switch (kind) {
          case 0:
            bad.nx = 65;
            break;
          case 1:
            bad.num_occupied += 1;
            break;
          case 2:
            bad.voxel_mm = std::numeric_limits<float>::quiet_NaN();
            break;
          case 3:
            bad.payload.resize(bad.payload.size() / 2);
            bad.payload_size = static_cast<int32_t>(bad.payload.size());
            break;
          default: {  // cut short on the wire: wire::decode refuses it
            std::vector<uint8_t> b(static_cast<size_t>(bad.getEncodedSize()));
            bad.encode(b.data(), 0, static_cast<int>(b.size()));
            bus->publish("HULL", std::span<const uint8_t>(b.data(), b.size() - 7));
            send = false;
            break;
          }
        }
        if (send) hullpose::wire::publish(*bus, "HULL", bad, scratch);
      }
    }
    if (k % static_cast<long long>(rate) == 0) {
      for (int c = -1; c < static_cast<int>(rig.cameras.size()); ++c) {
        hullpose_msg::node_status_t s{};
        s.utime = hullpose::realtime_utime();
        s.rig_id = rig.rig_id;
        s.role = c < 0 ? "fusion_host" : "camera_node";
        s.node_id = c < 0 ? -1 : rig.cameras[static_cast<size_t>(c)].id;
        s.hostname = "sim";
        s.state = hullpose_msg::node_status_t::STATE_RUNNING;
        s.fps = static_cast<float>(rate);
        s.frames_total = k;
        s.last_trigger_seq = k;
        s.num_stages = 0;
        s.counter_name = c < 0 ? std::vector<std::string>{"late"}
                               : std::vector<std::string>{"queue_full", "trigger_residual_mean_us",
                                                          "trigger_residual_max_us"};
        s.counter_value =
            c < 0 ? std::vector<int64_t>{0} : std::vector<int64_t>{c, 150 + 10 * c, 400 + 20 * c};
        s.num_counters = static_cast<int32_t>(s.counter_name.size());
        hullpose::wire::publish(*bus, "STATUS", s, scratch);
      }
    }
    pacer.wait_next();
  }
  if (hull_publisher) hull_publisher->drain();
  return 0;
}

int main(int argc, char** argv) {
  return hullpose::run_tool("consumers_sim_rig", argc, argv, run);
}
