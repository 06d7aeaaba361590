#include "hullpose/camera_node/publisher.hpp"

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"
#include "hullpose/msg/wire.hpp"

namespace hullpose::camera_node {
namespace {
HULLPOSE_LOG_CATEGORY(Publish, "publisher")
}

SilhouettePublisher::SilhouettePublisher(const LcmConfig& config, bus::Bus& bus, std::string rig_id,
                                         int camera_id, Counters& counters)
    : config_(config),
      rig_id_(std::move(rig_id)),
      camera_id_(camera_id),
      counters_(counters),
      bus_(bus) {
  scratch_.resize(128 * 1024);  // a silhouette of any person, and a status, without allocating
  // Named up front: a counter allocates its name on first use, which must not be on the frame path.
  counters_.add("queue_full", 0);
  counters_.add("publish_error", 0);
  ring_.resize(static_cast<size_t>(config.queue_depth));
  for (auto& m : ring_) {
    // Room for any silhouette a person makes (a few kB) and then some, reserved now: which slot
    // a frame lands in depends on the network thread's timing, so sizing on first use would
    // allocate on the frame path whenever the ring wraps differently.
    m.payload.reserve(64 * 1024);
    m.rig_id = rig_id_;
    m.camera_id = camera_id_;
    m.encoding = hullpose_msg::silhouette_t::ENCODING_RLE_V1;
  }
  thread_ = std::thread([this] { run(); });
}

SilhouettePublisher::~SilhouettePublisher() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

bool SilhouettePublisher::publish(const cv::Mat& mask, const SilhouetteStamp& stamp,
                                  int32_t* encode_us) {
  std::unique_lock lock(mutex_);
  if (count_ == ring_.size()) {
    lock.unlock();
    if (encode_us) *encode_us = 0;
    counters_.add("queue_full");
    HULLPOSE_LOG(Publish, Debug) << "camera " << camera_id_ << ": silhouette of trigger "
                                 << stamp.trigger_seq << " dropped: network queue full";
    return false;
  }
  // The slot at the tail is ours: the publisher thread only reads slots inside [head, head+count).
  hullpose_msg::silhouette_t& m = ring_[(head_ + count_) % ring_.size()];
  lock.unlock();

  const StageTimer timer;
  const PixelRoi roi = encoder_.encode(mask, m.payload);
  const int32_t enc_us = static_cast<int32_t>(timer.elapsed_us());
  m.utime = stamp.trigger_utime;
  m.trigger_seq = stamp.trigger_seq;
  m.capture_utime = stamp.capture_utime;
  m.width = mask.cols;
  m.height = mask.rows;
  m.roi_x = roi.x;
  m.roi_y = roi.y;
  m.roi_width = roi.width;
  m.roi_height = roi.height;
  m.payload_size = static_cast<int32_t>(m.payload.size());
  m.capture_us = stamp.capture_us;
  m.subtract_us = stamp.subtract_us;
  m.morphology_us = stamp.morphology_us;
  m.encode_us = enc_us;
  m.node_done_utime = realtime_utime() - stamp.clock_offset_us;
  if (encode_us) *encode_us = enc_us;

  lock.lock();
  ++count_;
  lock.unlock();
  wake_.notify_one();
  return true;
}

void SilhouettePublisher::publish_status(const hullpose_msg::node_status_t& status) {
  {
    std::lock_guard lock(mutex_);
    status_ = status;
  }
  wake_.notify_one();
}

void SilhouettePublisher::flush() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return (count_ == 0 && !status_ && !sending_) || stopping_; });
}

int64_t SilhouettePublisher::bytes_sent() const {
  std::lock_guard lock(mutex_);
  return bytes_sent_;
}

int64_t SilhouettePublisher::messages_sent() const {
  std::lock_guard lock(mutex_);
  return messages_sent_;
}

void SilhouettePublisher::run() {
  std::unique_lock lock(mutex_);
  std::optional<hullpose_msg::node_status_t> status;
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || count_ > 0 || status_; });
    if (status_) {
      status = std::move(status_);
      status_.reset();
      sending_ = true;
      lock.unlock();
      if (!wire::publish(bus_, config_.status_channel, *status, scratch_))
        counters_.add("publish_error");
      lock.lock();
      sending_ = false;
    } else if (count_ > 0) {
      const hullpose_msg::silhouette_t& m = ring_[head_];
      sending_ = true;
      lock.unlock();
      // Encoded here: this thread, not capture, pays for it.
      const bool sent = wire::publish(bus_, config_.silhouette_channel, m, scratch_);
      if (!sent) counters_.add("publish_error");
      lock.lock();
      sending_ = false;
      if (sent) {
        bytes_sent_ += m.getEncodedSize();
        ++messages_sent_;
      }
      head_ = (head_ + 1) % ring_.size();
      --count_;
    } else if (stopping_) {
      break;
    }
    if (count_ == 0 && !status_) idle_.notify_all();
  }
  idle_.notify_all();
}

}  // namespace hullpose::camera_node
