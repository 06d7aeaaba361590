#include "hullpose/camera_node/libcamera_source.hpp"

#include <libcamera/libcamera.h>
#include <sys/mman.h>

#include <chrono>
#include <condition_variable>
#include <ctime>
#include <deque>
#include <fstream>
#include <mutex>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"

namespace hullpose::camera_node {
namespace {

HULLPOSE_LOG_CATEGORY(Libcam, "libcamera_source")

int64_t boottime_to_epoch_us() {
  timespec boot{}, real{};
  clock_gettime(CLOCK_BOOTTIME, &boot);
  clock_gettime(CLOCK_REALTIME, &real);
  return (static_cast<int64_t>(real.tv_sec) - boot.tv_sec) * 1000000 +
         (real.tv_nsec - boot.tv_nsec) / 1000;
}

}  // namespace

struct LibcameraSource::Impl {
  // Parameters.
  std::string camera_wanted;
  int exposure_us = 4000;
  float analogue_gain = 1.f;
  int64_t frame_duration_us = 33333;
  bool external_trigger = false;
  int buffer_count = 4;
  cv::Size size;
  int camera_id = 0;

  // libcamera objects, in the order they must be destroyed (reverse).
  std::unique_ptr<libcamera::CameraManager> manager;
  std::shared_ptr<libcamera::Camera> camera;
  bool acquired = false, running = false;
  std::unique_ptr<libcamera::CameraConfiguration> config;
  std::unique_ptr<libcamera::FrameBufferAllocator> allocator;
  std::vector<std::unique_ptr<libcamera::Request>> requests;
  struct Mapping {
    void* data;
    size_t length;
  };
  std::vector<std::pair<const libcamera::FrameBuffer*, Mapping>> mappings;
  libcamera::Stream* stream = nullptr;
  std::string trigger_path;  // sysfs parameter set while streaming in trigger mode

  std::mutex mutex;
  std::condition_variable completed_cv;
  std::deque<libcamera::Request*> completed;  // bounded by the number of requests
  int64_t first_sequence = -1;
  cv::Mat image;

  std::string who() const { return "camera " + std::to_string(camera_id) + ": libcamera"; }

  void on_complete(libcamera::Request* request) {
    if (request->status() == libcamera::Request::RequestCancelled) return;
    {
      std::lock_guard lock(mutex);
      completed.push_back(request);
    }
    completed_cv.notify_one();
  }

  const Mapping* mapping_of(const libcamera::FrameBuffer* fb) const {
    for (const auto& [b, m] : mappings)
      if (b == fb) return &m;
    return nullptr;
  }

  void set_trigger_mode(bool on) {
    std::ofstream f(trigger_path);
    f << (on ? "1" : "0") << std::flush;
    HULLPOSE_THROW_UNLESS(f.good(),
                          who() << ": cannot write " << trigger_path << " (external trigger mode)");
  }

  void release() {
    if (running) {
      camera->stop();
      running = false;
    }
    if (!trigger_path.empty()) {
      try {
        set_trigger_mode(false);
      } catch (const Error& e) {
        HULLPOSE_LOG(Libcam, Warn) << e.what();
      }
      trigger_path.clear();
    }
    if (camera) camera->requestCompleted.disconnect(this);
    requests.clear();
    for (auto& [b, m] : mappings) munmap(m.data, m.length);
    mappings.clear();
    allocator.reset();
    config.reset();
    if (acquired) {
      camera->release();
      acquired = false;
    }
    camera.reset();
    if (manager) {
      manager->stop();
      manager.reset();
    }
    completed.clear();
  }
};

LibcameraSource::LibcameraSource(const Params& params, const SourceContext& context)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.camera_wanted = params.get_string("camera", "");
  m.exposure_us = params.get_int("exposure_us", 4000, 1, 10000000);
  m.analogue_gain = static_cast<float>(params.get_double("analogue_gain", 1.0, 1.0, 64.0));
  m.frame_duration_us = params.get_int("frame_duration_us", 33333, 100, 10000000);
  m.external_trigger = params.get_bool("external_trigger", false);
  m.buffer_count = params.get_int("buffers", 4, 2, 16);
  m.size = cv::Size(context.camera.width, context.camera.height);
  m.camera_id = context.camera_id;
  HULLPOSE_THROW_UNLESS(m.exposure_us <= m.frame_duration_us,
                        params.scope() << ".exposure_us: " << m.exposure_us
                                       << " exceeds frame_duration_us " << m.frame_duration_us);
}

LibcameraSource::~LibcameraSource() {
  stop();
}

std::string LibcameraSource::describe() const {
  const Impl& m = *impl_;
  return "libcamera " +
         (m.camera ? m.camera->id()
                   : (m.camera_wanted.empty() ? "(first camera)" : m.camera_wanted)) +
         " " + std::to_string(m.size.width) + "x" + std::to_string(m.size.height) +
         " RGB888, exposure " + std::to_string(m.exposure_us) + " us" +
         (m.external_trigger ? ", external trigger" : "");
}

void LibcameraSource::start() {
  using namespace libcamera;
  Impl& m = *impl_;
  m.manager = std::make_unique<CameraManager>();
  if (const int r = m.manager->start(); r < 0) {
    m.manager.reset();
    HULLPOSE_THROW(m.who() << ": CameraManager failed to start (error " << r << ")");
  }
  const auto cameras = m.manager->cameras();
  std::string listed;
  for (const auto& c : cameras) listed += (listed.empty() ? "" : ", ") + c->id();
  if (m.camera_wanted.empty()) {
    if (!cameras.empty()) m.camera = cameras.front();
  } else {
    m.camera = m.manager->get(m.camera_wanted);
    if (!m.camera && m.camera_wanted.find_first_not_of("0123456789") == std::string::npos) {
      const size_t index = std::stoul(m.camera_wanted);
      if (index < cameras.size()) m.camera = cameras[index];
    }
  }
  if (!m.camera) {
    m.release();
    HULLPOSE_THROW(m.who() << ": camera '"
                           << (m.camera_wanted.empty() ? "(first)" : m.camera_wanted)
                           << "' not found; the libcamera CameraManager listed "
                           << (listed.empty() ? "no cameras" : listed)
                           << " (is the sensor connected and its device tree overlay loaded?)");
  }
  if (m.camera->acquire() < 0) {
    const std::string id = m.camera->id();
    m.release();
    HULLPOSE_THROW(m.who() << ": camera " << id << " is busy (acquire failed)");
  }
  m.acquired = true;

  if (m.external_trigger) {
    const auto model = m.camera->properties().get(properties::Model);
    const std::string sensor = model ? *model : std::string("unknown");
    m.trigger_path = "/sys/module/" + sensor + "/parameters/trigger_mode";
    if (!std::ifstream(m.trigger_path).good()) {
      const std::string path = m.trigger_path;
      m.trigger_path.clear();
      m.release();
      HULLPOSE_THROW(m.who() << ": sensor " << sensor << " has no external-trigger mode (tried "
                             << path << ")");
    }
    m.set_trigger_mode(true);
  }

  m.config = m.camera->generateConfiguration({StreamRole::VideoRecording});
  HULLPOSE_THROW_UNLESS(m.config && m.config->size() == 1,
                        m.who() << ": no configuration for a video stream");
  StreamConfiguration& sc = m.config->at(0);
  sc.size = Size(static_cast<unsigned>(m.size.width), static_cast<unsigned>(m.size.height));
  sc.pixelFormat = formats::RGB888;  // DRM order: bytes B, G, R in memory = OpenCV BGR
  sc.bufferCount = static_cast<unsigned>(m.buffer_count);
  const auto status = m.config->validate();
  if (status == CameraConfiguration::Invalid || sc.pixelFormat != formats::RGB888 ||
      sc.size != Size(static_cast<unsigned>(m.size.width), static_cast<unsigned>(m.size.height))) {
    const std::string offered = sc.toString();
    m.release();
    HULLPOSE_THROW(m.who() << ": camera does not offer " << m.size.width << "x" << m.size.height
                           << "-RGB888 (offered " << offered << ")");
  }
  if (m.camera->configure(m.config.get()) < 0) {
    m.release();
    HULLPOSE_THROW(m.who() << ": configure failed");
  }
  m.stream = sc.stream();
  m.allocator = std::make_unique<FrameBufferAllocator>(m.camera);
  if (m.allocator->allocate(m.stream) < 0) {
    m.release();
    HULLPOSE_THROW(m.who() << ": cannot allocate frame buffers");
  }
  for (const std::unique_ptr<FrameBuffer>& fb : m.allocator->buffers(m.stream)) {
    size_t length = 0;
    for (const FrameBuffer::Plane& p : fb->planes())
      length = std::max<size_t>(length, p.offset + p.length);
    void* data = mmap(nullptr, length, PROT_READ, MAP_SHARED, fb->planes()[0].fd.get(), 0);
    if (data == MAP_FAILED) {
      m.release();
      HULLPOSE_THROW(m.who() << ": cannot mmap a frame buffer");
    }
    m.mappings.push_back({fb.get(), Impl::Mapping{data, length}});
    std::unique_ptr<Request> request = m.camera->createRequest();
    if (!request || request->addBuffer(m.stream, fb.get()) < 0) {
      m.release();
      HULLPOSE_THROW(m.who() << ": cannot create a capture request");
    }
    m.requests.push_back(std::move(request));
  }

  // Fixed exposure, gain and frame duration: the rig needs every camera to expose alike and on
  // time.
  ControlList controls(controls::controls);
  controls.set(controls::AeEnable, false);
  controls.set(controls::ExposureTime, m.exposure_us);
  controls.set(controls::AnalogueGain, m.analogue_gain);
  const int64_t limits[2] = {m.frame_duration_us, m.frame_duration_us};
  controls.set(controls::FrameDurationLimits, Span<const int64_t, 2>(limits));
  m.camera->requestCompleted.connect(&m, &Impl::on_complete);
  if (m.camera->start(&controls) < 0) {
    m.release();
    HULLPOSE_THROW(m.who() << ": start failed");
  }
  m.running = true;
  for (auto& r : m.requests) {
    if (m.camera->queueRequest(r.get()) < 0) {
      m.release();
      HULLPOSE_THROW(m.who() << ": queueRequest failed");
    }
  }
  m.first_sequence = -1;
  m.image.create(m.size, CV_8UC3);
  HULLPOSE_LOG(Libcam, Info) << "camera " << m.camera_id << ": streaming " << describe();
}

GrabStatus LibcameraSource::grab(Frame& frame, int timeout_ms) {
  using namespace libcamera;
  Impl& m = *impl_;
  HULLPOSE_ASSERT(m.running);
  Request* request = nullptr;
  {
    std::unique_lock lock(m.mutex);
    if (!m.completed_cv.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                                 [&] { return !m.completed.empty(); }))
      return GrabStatus::kTimeout;
    request = m.completed.front();
    m.completed.pop_front();
  }
  const FrameBuffer* fb = request->findBuffer(m.stream);
  const Impl::Mapping* map = fb ? m.mapping_of(fb) : nullptr;
  HULLPOSE_THROW_UNLESS(map, m.who() << ": completed request without a known buffer");
  const StreamConfiguration& sc = m.config->at(0);
  cv::Mat(m.size, CV_8UC3, static_cast<uint8_t*>(map->data) + fb->planes()[0].offset, sc.stride)
      .copyTo(m.image);
  const int64_t seq = fb->metadata().sequence;
  if (m.first_sequence < 0) m.first_sequence = seq;
  frame.image = m.image;
  frame.sequence = seq - m.first_sequence;
  const auto ts = request->metadata().get(controls::SensorTimestamp);
  const int64_t ns = ts ? *ts : static_cast<int64_t>(fb->metadata().timestamp);
  frame.capture_utime = ns / 1000 + boottime_to_epoch_us();
  request->reuse(Request::ReuseBuffers);
  HULLPOSE_THROW_UNLESS(
      m.camera->queueRequest(request) == 0,
      m.who() << ": camera " << m.camera->id() << " stopped accepting requests (disconnected?)");
  return GrabStatus::kFrame;
}

void LibcameraSource::stop() {
  if (impl_) impl_->release();
}

}  // namespace hullpose::camera_node
