#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hullpose/common/joints.hpp"
#include "hullpose/listen/skeleton_log.hpp"

using namespace hullpose;

namespace {
hullpose_msg::skeleton_t skeleton(int64_t seq, bool valid, int32_t published_us, int cams = 8) {
  hullpose_msg::skeleton_t s{};
  s.utime = 1000 + seq;
  s.rig_id = "rigA";
  s.trigger_seq = seq;
  s.num_joints = kNumJoints;
  s.joint_name.assign(kJointNames.begin(), kJointNames.end());
  s.position.assign(kNumJoints, {1.5f, -2.f, static_cast<float>(seq)});
  s.confidence.assign(kNumJoints, 1.f);
  s.valid = valid;
  s.reason = valid ? 0 : 1;
  s.model_version = 3;
  s.num_cameras_used = cams;
  s.cameras_used_mask = 0xFF;
  s.capture_us = 100;
  s.node_done_us = 2000;
  s.received_us = 2500;
  s.fused_us = published_us - 500;
  s.published_us = published_us;
  return s;
}
}  // namespace

TEST_CASE("latency percentiles, missing sequences and reasons") {
  listen::SkeletonStats st;
  for (int64_t seq = 0; seq < 100; ++seq) {
    if (seq == 50 || seq == 51) continue;  // never received
    st.add(skeleton(seq, seq % 10 != 0, static_cast<int32_t>(1000 * (seq + 1))));
  }
  CHECK(st.received() == 98);
  CHECK(st.valid() == 89);  // 0, 10, ..., 90 invalid, 50 never received
  CHECK(st.missing_sequences() == 2);
  const auto& pub = st.stage(4);
  CHECK(pub.count() == 98);
  CHECK(pub.percentile_ms(0.5) == Approx(51.0).margin(1.0));
  CHECK(pub.percentile_ms(0.99) == Approx(100.0).margin(1.0));
  CHECK(pub.max_ms() == Approx(100.0));
  const auto json = nlohmann::json::parse(st.summary_json());
  CHECK(json["skeletons"] == 98);
  CHECK(json["reasons"]["too_few_cameras"] == 9);
  CHECK(json["latency_ms"]["published"]["p50"].get<double>() == Approx(51.0).margin(1.0));
  // Frames without views carry no breakdown and do not count in the latency series.
  st.add(skeleton(100, false, -1, 0));
  CHECK(st.stage(4).count() == 98);
}

TEST_CASE("CSV, JSON lines and estimate rows have one field per header column") {
  std::ostringstream csv, jsonl, est;
  listen::write_csv_header(csv);
  listen::write_csv(csv, skeleton(7, true, 9000));
  listen::write_jsonl(jsonl, skeleton(7, true, 9000));
  listen::write_estimate_header(est);
  listen::write_estimate(est, skeleton(107, true, 9000), 100);
  auto fields = [](const std::string& line) {
    return std::count(line.begin(), line.end(), ',') + 1;
  };
  std::istringstream c(csv.str()), e(est.str());
  std::string h, row;
  std::getline(c, h);
  std::getline(c, row);
  CHECK(fields(h) == 11 + 75);
  CHECK(fields(row) == fields(h));
  CHECK(row.rfind("7,1007,1,0,8,255,100,2000,2500,8500,9000,1.5,-2,7", 0) == 0);
  std::getline(e, h);
  std::getline(e, row);
  CHECK(h.rfind("frame,valid,reason,model,HeadTop_x,HeadTop_y,HeadTop_z", 0) == 0);
  CHECK(fields(row) == fields(h));
  CHECK(row.rfind("7,1,0,3,1.5,-2,107", 0) == 0);
  CHECK_THAT(jsonl.str(), Catch::EndsWith("}\n"));
  const auto line = nlohmann::json::parse(jsonl.str());
  CHECK(line["trigger_seq"] == 7);
  CHECK(line["joints"]["RToe"] == nlohmann::json::array({1.5, -2.0, 7.0}));
}
