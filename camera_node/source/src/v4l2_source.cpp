#include "hullpose/camera_node/v4l2_source.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <opencv2/imgproc.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::camera_node {
namespace {

HULLPOSE_LOG_CATEGORY(V4l2, "v4l2")

int xioctl(int fd, unsigned long request, void* arg) {
  int r;
  do r = ioctl(fd, request, arg);
  while (r == -1 && errno == EINTR);
  return r;
}

uint32_t parse_fourcc(const std::string& s, const std::string& field) {
  if (s == "YUYV") return V4L2_PIX_FMT_YUYV;
  if (s == "BGR3") return V4L2_PIX_FMT_BGR24;
  if (s == "RGB3") return V4L2_PIX_FMT_RGB24;
  if (s == "GREY") return V4L2_PIX_FMT_GREY;
  HULLPOSE_THROW(field << ": unsupported pixel format '" << s
                       << "' (supported: YUYV, BGR3, RGB3, GREY)");
}

std::string fourcc_text(uint32_t f) {
  return {static_cast<char>(f & 0xff), static_cast<char>((f >> 8) & 0xff),
          static_cast<char>((f >> 16) & 0xff), static_cast<char>((f >> 24) & 0xff)};
}

// Offset from CLOCK_MONOTONIC to the epoch, for driver timestamps.
int64_t monotonic_to_epoch_us() {
  timespec mono{}, real{};
  clock_gettime(CLOCK_MONOTONIC, &mono);
  clock_gettime(CLOCK_REALTIME, &real);
  return (static_cast<int64_t>(real.tv_sec) - mono.tv_sec) * 1000000 +
         (real.tv_nsec - mono.tv_nsec) / 1000;
}

}  // namespace

V4l2Source::V4l2Source(const Params& params, const SourceContext& context)
    : size_(context.camera.width, context.camera.height), camera_id_(context.camera_id) {
  device_ = params.get_string("device", "/dev/video0");
  fourcc_ =
      parse_fourcc(params.get_string("pixel_format", "YUYV"), params.scope() + ".pixel_format");
  buffer_count_ = params.get_int("buffers", 4, 2, 32);
}

V4l2Source::~V4l2Source() {
  stop();
}

std::string V4l2Source::describe() const {
  return "v4l2 " + device_ + " " + std::to_string(size_.width) + "x" +
         std::to_string(size_.height) + " " + fourcc_text(fourcc_);
}

void V4l2Source::start() {
  const std::string who = "camera " + std::to_string(camera_id_) + ": v4l2 device " + device_;
  fd_ = ::open(device_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    const int err = errno;
    HULLPOSE_THROW(
        who << ": cannot open (" << std::strerror(err) << "); tried open(2) read-write"
            << (err == ENOENT
                    ? "; no such device node — is the camera connected and its driver loaded?"
                    : ""));
  }
  v4l2_capability cap{};
  if (xioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0) {
    const int err = errno;
    stop();
    HULLPOSE_THROW(who << ": not a V4L2 device (VIDIOC_QUERYCAP: " << std::strerror(err) << ")");
  }
  const uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
    stop();
    HULLPOSE_THROW(who << " (" << reinterpret_cast<const char*>(cap.card)
                       << "): no single-planar video capture with streaming I/O");
  }
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = static_cast<uint32_t>(size_.width);
  fmt.fmt.pix.height = static_cast<uint32_t>(size_.height);
  fmt.fmt.pix.pixelformat = fourcc_;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (xioctl(fd_, VIDIOC_S_FMT, &fmt) < 0 || fmt.fmt.pix.pixelformat != fourcc_ ||
      fmt.fmt.pix.width != static_cast<uint32_t>(size_.width) ||
      fmt.fmt.pix.height != static_cast<uint32_t>(size_.height)) {
    stop();
    HULLPOSE_THROW(who << ": does not accept " << size_.width << "x" << size_.height << " "
                       << fourcc_text(fourcc_) << " (driver offered " << fmt.fmt.pix.width << "x"
                       << fmt.fmt.pix.height << " " << fourcc_text(fmt.fmt.pix.pixelformat) << ")");
  }
  stride_ = fmt.fmt.pix.bytesperline;
  v4l2_requestbuffers req{};
  req.count = static_cast<uint32_t>(buffer_count_);
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_REQBUFS, &req) < 0 || req.count < 2) {
    stop();
    HULLPOSE_THROW(who << ": cannot get mmap buffers (VIDIOC_REQBUFS)");
  }
  buffers_.assign(req.count, Buffer{});
  for (uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    buf.index = i;
    if (xioctl(fd_, VIDIOC_QUERYBUF, &buf) < 0) {
      stop();
      HULLPOSE_THROW(who << ": VIDIOC_QUERYBUF failed for buffer " << i);
    }
    void* data = mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, buf.m.offset);
    if (data == MAP_FAILED) {
      stop();
      HULLPOSE_THROW(who << ": mmap of buffer " << i << " failed");
    }
    buffers_[i] = Buffer{data, buf.length};
    if (xioctl(fd_, VIDIOC_QBUF, &buf) < 0) {
      stop();
      HULLPOSE_THROW(who << ": VIDIOC_QBUF failed for buffer " << i);
    }
  }
  v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (xioctl(fd_, VIDIOC_STREAMON, &type) < 0) {
    const int err = errno;
    stop();
    HULLPOSE_THROW(who << ": VIDIOC_STREAMON failed (" << std::strerror(err) << ")");
  }
  streaming_ = true;
  first_sequence_ = -1;
  image_.create(size_, CV_8UC3);
  HULLPOSE_LOG(V4l2, Info) << "camera " << camera_id_ << ": streaming " << describe();
}

GrabStatus V4l2Source::grab(Frame& frame, int timeout_ms) {
  HULLPOSE_ASSERT(streaming_);
  pollfd pfd{fd_, POLLIN, 0};
  const int r = poll(&pfd, 1, timeout_ms);
  if (r == 0) return GrabStatus::kTimeout;
  if (r < 0 && errno == EINTR) return GrabStatus::kTimeout;
  HULLPOSE_THROW_UNLESS(r > 0 && !(pfd.revents & (POLLERR | POLLHUP | POLLNVAL)),
                        "camera " << camera_id_ << ": v4l2 device " << device_
                                  << " stopped delivering frames"
                                  << " (poll error; device unplugged?)");
  v4l2_buffer buf{};
  buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  buf.memory = V4L2_MEMORY_MMAP;
  if (xioctl(fd_, VIDIOC_DQBUF, &buf) < 0) {
    if (errno == EAGAIN) return GrabStatus::kTimeout;
    HULLPOSE_THROW("camera " << camera_id_ << ": v4l2 device " << device_
                             << ": VIDIOC_DQBUF failed (" << std::strerror(errno) << ")");
  }
  uint8_t* data = static_cast<uint8_t*>(buffers_[buf.index].data);
  const int w = size_.width, h = size_.height;
  switch (fourcc_) {
    case V4L2_PIX_FMT_YUYV:
      cv::cvtColor(cv::Mat(h, w, CV_8UC2, data, stride_), image_, cv::COLOR_YUV2BGR_YUYV);
      break;
    case V4L2_PIX_FMT_BGR24:
      cv::Mat(h, w, CV_8UC3, data, stride_).copyTo(image_);
      break;
    case V4L2_PIX_FMT_RGB24:
      cv::cvtColor(cv::Mat(h, w, CV_8UC3, data, stride_), image_, cv::COLOR_RGB2BGR);
      break;
    default:
      cv::cvtColor(cv::Mat(h, w, CV_8UC1, data, stride_), image_, cv::COLOR_GRAY2BGR);
      break;
  }
  if (first_sequence_ < 0) first_sequence_ = buf.sequence;
  frame.image = image_;
  frame.sequence = static_cast<int64_t>(buf.sequence) - first_sequence_;
  frame.capture_utime =
      static_cast<int64_t>(buf.timestamp.tv_sec) * 1000000 + buf.timestamp.tv_usec;
  if ((buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC)
    frame.capture_utime += monotonic_to_epoch_us();
  HULLPOSE_THROW_UNLESS(xioctl(fd_, VIDIOC_QBUF, &buf) == 0,
                        "camera " << camera_id_ << ": v4l2 device " << device_
                                  << ": VIDIOC_QBUF failed (" << std::strerror(errno) << ")");
  return GrabStatus::kFrame;
}

void V4l2Source::stop() {
  if (fd_ < 0) return;
  if (streaming_) {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    xioctl(fd_, VIDIOC_STREAMOFF, &type);
    streaming_ = false;
  }
  for (Buffer& b : buffers_)
    if (b.data) munmap(b.data, b.length);
  buffers_.clear();
  ::close(fd_);
  fd_ = -1;
}

}  // namespace hullpose::camera_node
