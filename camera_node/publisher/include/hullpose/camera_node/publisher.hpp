#pragma once
// Sends a camera node's silhouettes (channel SILHOUETTE, hullpose_msg::silhouette_t) and health
// (channel STATUS, node_status_t) on the process's bus.
//
// The network never blocks capture: publish() encodes the mask on the caller's thread into a
// slot of a bounded ring and returns; a publisher thread sends the slots. When the ring is full
// the new silhouette is dropped and counted ("queue_full"). Slots are preallocated and reused, so
// publish() does not allocate at steady state. STATUS goes through a one-message mailbox (the
// latest status wins).
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "hullpose/camera_node/node_config.hpp"
#include "hullpose/common/bus.hpp"
#include "hullpose/common/counters.hpp"
#include "hullpose/common/silhouette_codec.hpp"
#include "hullpose_msg/node_status_t.hpp"
#include "hullpose_msg/silhouette_t.hpp"

namespace hullpose::camera_node {

// Everything in a silhouette_t besides the mask.
struct SilhouetteStamp {
  int64_t trigger_seq = 0;
  int64_t trigger_utime = 0;
  int64_t capture_utime = 0;
  int64_t clock_offset_us =
      0;  // node realtime clock - master clock: node_done_utime is on the master's
  int32_t capture_us = 0;
  int32_t subtract_us = 0;
  int32_t morphology_us = 0;
};

class SilhouettePublisher {
 public:
  // Starts the publisher thread, which sends on `bus` (outlives the publisher; its publish() is
  // thread-safe).
  SilhouettePublisher(const LcmConfig& config, bus::Bus& bus, std::string rig_id, int camera_id,
                      Counters& counters);
  ~SilhouettePublisher();
  SilhouettePublisher(const SilhouettePublisher&) = delete;
  SilhouettePublisher& operator=(const SilhouettePublisher&) = delete;

  // Encodes `mask` (CV_8UC1) and queues it; returns false if the ring was full (counted
  // "queue_full"). Returns the encode time in `encode_us`. One producer: call from one thread.
  bool publish(const cv::Mat& mask, const SilhouetteStamp& stamp, int32_t* encode_us = nullptr);
  // Queues a status message (replacing one not yet sent).
  void publish_status(const hullpose_msg::node_status_t& status);
  // Waits until everything queued has been handed to LCM.
  void flush();

  int64_t bytes_sent() const;
  int64_t messages_sent() const;

 private:
  void run();

  LcmConfig config_;
  std::string rig_id_;
  int camera_id_;
  Counters& counters_;
  bus::Bus& bus_;
  std::vector<uint8_t> scratch_;  // the publisher thread's encode buffer, reused
  SilhouetteEncoder encoder_;

  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  std::vector<hullpose_msg::silhouette_t> ring_;
  size_t head_ = 0, count_ = 0;
  bool sending_ = false;
  std::optional<hullpose_msg::node_status_t> status_;
  bool stopping_ = false;
  int64_t bytes_sent_ = 0, messages_sent_ = 0;
  std::thread thread_;
};

}  // namespace hullpose::camera_node
