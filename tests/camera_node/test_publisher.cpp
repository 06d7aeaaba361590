#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "hullpose/camera_node/publisher.hpp"
#include "hullpose/common/check.hpp"

using namespace hullpose;
using namespace hullpose::camera_node;

TEST_CASE("every silhouette handed to the publisher is either sent or counted as dropped") {
  LcmConfig config;
  config.url = "memq://";
  config.queue_depth = 1;  // the smallest ring: a burst must overflow it or be sent in time
  Counters counters;
  constexpr int kBurst = 500;
  {
    const auto bus = bus::open_bus(config.url);
    SilhouettePublisher publisher(config, *bus, "rig", 2, counters);
    cv::Mat mask(120, 160, CV_8UC1, cv::Scalar(0));
    cv::circle(mask, {80, 60}, 30, cv::Scalar(255), -1);
    int accepted = 0;
    for (int i = 0; i < kBurst; ++i) {
      int32_t encode_us = -1;
      accepted += publisher.publish(mask, SilhouetteStamp{i, i, i, 0, 0, 0}, &encode_us);
      CHECK(encode_us >= 0);
    }
    publisher.flush();
    CHECK(publisher.messages_sent() == accepted);
    CHECK(accepted + counters.get("queue_full") == kBurst);
    CHECK(publisher.bytes_sent() > 0);
  }
  CHECK(counters.get("publish_error") == 0);
}

TEST_CASE("a bad LCM URL is an error naming it") {
  CHECK_THROWS_WITH(bus::open_bus("udpm://not-an-address:x"),
                    Catch::Contains("LCM 'udpm://not-an-address:x' cannot be opened"));
}
