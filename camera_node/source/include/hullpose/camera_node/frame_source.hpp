#pragma once
// Where a camera node's frames come from. One interface, several backends registered by name and
// chosen in the node's config (source.type): libcamera (the production camera), v4l2 (mmap
// streaming), file (image sequence or video replay) and synthetic (the simulated rig).
//
// Lifecycle:  make_source(...) (parses and checks parameters, opens nothing)
//             -> start() (opens the device; throws hullpose::Error naming the device and what
//                was tried if it is absent) -> grab() ... -> stop().
//
// Every frame carries the source's frame counter and the sensor's capture timestamp, which the
// trigger layer (camera_node/trigger) matches to the trigger announcements.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "hullpose/camera_node/params.hpp"
#include "hullpose/common/camera.hpp"
#include "hullpose/common/rig.hpp"

namespace hullpose::camera_node {

struct Frame {
  // CV_8UC3, BGR. Owned by the source and reused: valid until the next grab() on that source.
  cv::Mat image;
  // The source's frame counter: 0 for the first frame after start(), +1 per frame the sensor
  // produced (a gap means the sensor or driver dropped frames).
  int64_t sequence = 0;
  // Start of exposure, microseconds since the Unix epoch on this node's clock, from the sensor
  // (libcamera SensorTimestamp, V4L2 buffer timestamp) or the replayed file's timing; 0 if unknown.
  int64_t capture_utime = 0;
};

enum class GrabStatus {
  kFrame,        // `frame` holds a new frame
  kTimeout,      // no frame within the timeout (e.g. external trigger paused); try again
  kEndOfStream,  // a finite source (file) has no more frames
  // This frame could not be decoded (a corrupt or truncated file): the camera has no picture of
  // that instant and sends nothing for it; the node counts it (corrupt_frame) and goes on.
  kCorruptFrame,
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Opens the device and starts streaming. Throws hullpose::Error naming the device and what was
  // tried when it is absent or refuses the configuration.
  virtual void start() = 0;
  // Waits up to timeout_ms for the next frame. Throws hullpose::Error if the device vanished.
  virtual GrabStatus grab(Frame& frame, int timeout_ms) = 0;
  // Stops streaming and releases the device; safe to call twice.
  virtual void stop() = 0;
  // One line for logs: backend, device and format.
  virtual std::string describe() const = 0;

  // Simulated sensors (file, synthetic) can be triggered: after expose(), the next grab() returns
  // the scene at that trigger instant, frame `trigger_seq` of the recording or motion, stamped
  // capture_utime. The simulated world's clock is the trigger sequence, so every node of a
  // simulated rig shows the same instant for the same trigger, however late it started. Real
  // cameras take the trigger on their own input line and return false.
  virtual bool triggerable() const { return false; }
  virtual void expose(int64_t /*trigger_seq*/, int64_t /*capture_utime*/) {}
  // While the node waits for the next trigger, a simulated sensor may get that trigger's scene
  // ready (file replay decodes the file), so that its frame is ready at the edge as a real
  // sensor's is, instead of costing the decoding time after it.
  virtual void prepare(int64_t /*trigger_seq*/) {}
};

// What a backend learns about the camera it serves, besides its own parameters.
struct SourceContext {
  int camera_id = 0;
  CameraModel camera;              // from the rig file: the image size frames must have
  CaptureVolume volume;            // the rig's capture volume (where a simulated subject stands)
  std::filesystem::path base_dir;  // relative file paths in the parameters are relative to this
};

using SourceFactory =
    std::function<std::unique_ptr<FrameSource>(const Params&, const SourceContext&)>;

// Backends by name. builtin() holds libcamera, v4l2, file and synthetic (libcamera and synthetic
// only where the build has them: HULLPOSE_LIBCAMERA, HULLPOSE_SYNTHETIC_SOURCE); tests may add
// their own.
class SourceRegistry {
 public:
  static SourceRegistry& builtin();
  void add(std::string name, SourceFactory factory);
  // A backend this build left out (its library was not configured): choosing it is an error
  // that says why, rather than "unknown source".
  void add_unavailable(std::string name, std::string why);
  // Throws hullpose::Error for an unknown name (listing the known ones) or bad parameters.
  std::unique_ptr<FrameSource> create(const std::string& name, const Params& params,
                                      const SourceContext& context) const;
  std::vector<std::string> names() const;

 private:
  std::vector<std::pair<std::string, SourceFactory>> factories_;
};

}  // namespace hullpose::camera_node
