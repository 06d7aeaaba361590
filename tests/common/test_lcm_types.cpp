#include <catch2/catch.hpp>
#include <hullpose_msg/silhouette_t.hpp>
#include <hullpose_msg/skeleton_t.hpp>
#include <hullpose_msg/trigger_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <vector>

TEST_CASE("silhouette_t round-trips through LCM encoding and rejects truncation") {
  hullpose_msg::silhouette_t s{};
  s.utime = 1234567;
  s.rig_id = "r";
  s.camera_id = 3;
  s.trigger_seq = 99;
  s.encoding = hullpose_msg::silhouette_t::ENCODING_RLE_V1;
  s.payload = {1, 2, 3, 4};
  s.payload_size = 4;
  std::vector<uint8_t> buf(static_cast<size_t>(s.getEncodedSize()));
  REQUIRE(s.encode(buf.data(), 0, static_cast<int>(buf.size())) == static_cast<int>(buf.size()));
  hullpose_msg::silhouette_t back;
  REQUIRE(back.decode(buf.data(), 0, static_cast<int>(buf.size())) == static_cast<int>(buf.size()));
  CHECK(back.camera_id == 3);
  CHECK(back.payload == s.payload);
  CHECK(back.decode(buf.data(), 0, static_cast<int>(buf.size()) - 1) < 0);
}

TEST_CASE("messages travel over memq://") {
  lcm::LCM bus("memq://");
  REQUIRE(bus.good());
  struct Handler {
    int64_t seq = -1;
    void on(const lcm::ReceiveBuffer*, const std::string&, const hullpose_msg::trigger_t* m) {
      seq = m->seq;
    }
  } h;
  bus.subscribe("TRIGGER", &Handler::on, &h);
  hullpose_msg::trigger_t t{};
  t.seq = 41;
  t.rig_id = "r";
  bus.publish("TRIGGER", &t);
  REQUIRE(bus.handleTimeout(0) > 0);
  CHECK(h.seq == 41);
}
