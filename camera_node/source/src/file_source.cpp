#include "hullpose/camera_node/file_source.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "hullpose/common/check.hpp"
#include "hullpose/common/log.hpp"
#include "hullpose/common/time.hpp"

namespace hullpose::camera_node {

HULLPOSE_LOG_CATEGORY(FileSrc, "file_source")

namespace {

// The pattern's one "%d" or "%0Nd" replaced by the index. Done by hand rather than with printf:
// the pattern comes from a config file and must not be a format string.
struct IndexPattern {
  std::string prefix, suffix;
  int width = 0;

  static bool parse(const std::string& path, IndexPattern& out) {
    const size_t pos = path.find('%');
    if (pos == std::string::npos) return false;
    size_t i = pos + 1;
    int width = 0;
    while (i < path.size() && std::isdigit(static_cast<unsigned char>(path[i])))
      width = width * 10 + (path[i++] - '0');
    HULLPOSE_THROW_UNLESS(
        i < path.size() && path[i] == 'd' && width <= 12 && path.find('%', i) == std::string::npos,
        "file source: path '" << path << "' must contain exactly one %d or %0Nd");
    out = IndexPattern{path.substr(0, pos), path.substr(i + 1), width};
    return true;
  }
  std::string at(int index) const {
    std::string digits = std::to_string(index);
    if (static_cast<int>(digits.size()) < width)
      digits.insert(0, static_cast<size_t>(width) - digits.size(), '0');
    return prefix + digits + suffix;
  }
};

}  // namespace

FileSource::FileSource(const Params& params, const SourceContext& context)
    : size_(context.camera.width, context.camera.height), camera_id_(context.camera_id) {
  const std::filesystem::path p(params.require_string("path"));
  path_ = (p.is_absolute() ? p : context.base_dir / p).string();
  IndexPattern pattern;
  pattern_ = IndexPattern::parse(path_, pattern);
  prefix_ = pattern.prefix;
  suffix_ = pattern.suffix;
  width_ = pattern.width;
  fps_ = params.get_double("fps", 30.0, 0.001, 100000.0);
  start_utime_ = static_cast<int64_t>(params.get_double("start_utime", 0.0, 0.0, 9.2e18));
  first_index_ = params.get_int("first_index", 0, 0, 1 << 30);
  loop_ = params.get_bool("loop", false);
  preload_ = params.get_bool("preload", false);
}

std::string FileSource::describe() const {
  return "file " + path_ + (pattern_ ? " (image sequence)" : " (video)") +
         (loop_ ? ", looping" : "");
}

FileSource::Read FileSource::read_next(cv::Mat& out) {
  std::string what;
  if (pattern_) {
    const std::string name = IndexPattern{prefix_, suffix_, width_}.at(first_index_ + next_index_);
    if (!std::filesystem::exists(name)) return Read::kEnd;
    out = cv::imread(name, cv::IMREAD_COLOR);
    if (out.empty()) what = "image " + name + " does not decode";
  } else {
    // A failed read before the frame count the container states is a damaged frame; past it (or
    // with no count) the end of the video.
    if (!video_.read(out) || out.empty()) {
      if (count_ < 0 || next_index_ >= count_) return Read::kEnd;
      what = "frame " + std::to_string(next_index_) + " of " + path_ + " does not decode";
    }
  }
  if (!what.empty()) {
    ++next_index_;
    // The first few and then every 100th: a truncated video fails on every frame after the cut.
    if (++corrupt_ <= 3 || corrupt_ % 100 == 0) {
      HULLPOSE_LOG(FileSrc, Warn) << "camera " << camera_id_ << ": " << what
                                  << " (corrupt or truncated; " << corrupt_
                                  << " so far): no silhouette for it";
    }
    return Read::kCorrupt;
  }
  HULLPOSE_THROW_UNLESS(out.size() == size_,
                        "camera " << camera_id_ << ": file source " << path_ << ": frame "
                                  << next_index_ << " is " << out.cols << "x" << out.rows
                                  << ", the rig camera is " << size_.width << "x" << size_.height);
  ++next_index_;
  return Read::kFrame;
}

void FileSource::start() {
  next_index_ = 0;
  delivered_ = 0;
  t0_ = start_utime_ > 0 ? start_utime_ : realtime_utime();
  if (pattern_) {
    const std::string first = IndexPattern{prefix_, suffix_, width_}.at(first_index_);
    HULLPOSE_THROW_UNLESS(std::filesystem::exists(first),
                          "camera " << camera_id_ << ": file source: first image " << first
                                    << " not found (pattern " << path_ << ", first_index "
                                    << first_index_ << ")");
  } else {
    HULLPOSE_THROW_UNLESS(std::filesystem::exists(path_),
                          "camera " << camera_id_ << ": file source: " << path_ << " not found");
    HULLPOSE_THROW_UNLESS(
        video_.open(path_),
        "camera " << camera_id_ << ": file source: OpenCV cannot open video " << path_);
  }
  exposed_index_ = -1;
  prepared_index_ = -1;
  if (pattern_) {
    count_ = 0;
    while (
        std::filesystem::exists(IndexPattern{prefix_, suffix_, width_}.at(first_index_ + count_)))
      ++count_;
  } else {
    count_ = static_cast<int>(video_.get(cv::CAP_PROP_FRAME_COUNT));
    if (count_ <= 0) count_ = -1;
  }
  if (preload_) {
    frames_.clear();
    cv::Mat m;
    // A corrupt frame keeps its place as an empty one, so frame k is still trigger k's.
    for (Read r; (r = read_next(m)) != Read::kEnd;)
      frames_.push_back(r == Read::kFrame ? m.clone() : cv::Mat());
    next_index_ = 0;
    count_ = static_cast<int>(frames_.size());
  }
}

int64_t FileSource::frame_of(int64_t trigger_seq) const {
  HULLPOSE_THROW_UNLESS(trigger_seq >= 0, "camera " << camera_id_
                                                    << ": file source: trigger sequence "
                                                    << trigger_seq << " is negative");
  return loop_ && count_ > 0 ? trigger_seq % count_ : std::min<int64_t>(trigger_seq, 1 << 30);
}

void FileSource::expose(int64_t trigger_seq, int64_t capture_utime) {
  exposed_index_ = frame_of(trigger_seq);
  exposed_utime_ = capture_utime;
}

void FileSource::prepare(int64_t trigger_seq) {
  const int index = static_cast<int>(frame_of(trigger_seq));
  if (!pattern_ || preload_ || index == prepared_index_ || (count_ >= 0 && index >= count_)) return;
  const int saved = next_index_;
  next_index_ = index;
  prepared_index_ = read_next(prepared_) == Read::kFrame ? index : -1;
  next_index_ = saved;
}

void FileSource::seek(int index) {
  if (!pattern_ && !preload_ && index != next_index_) {
    // Frame-exact by decoding forward: CAP_PROP_POS_FRAMES lands on a nearby key frame in
    // inter-coded videos (XviD, H.264), and every node must show the trigger's own frame.
    if (index < next_index_) {
      video_.set(cv::CAP_PROP_POS_FRAMES, 0);
      next_index_ = 0;
    }
    while (next_index_ < index && video_.grab()) ++next_index_;
  }
  next_index_ = index;
}

GrabStatus FileSource::grab(Frame& frame, int /*timeout_ms*/) {
  const bool exposed = exposed_index_ >= 0;
  if (exposed) {
    seek(static_cast<int>(exposed_index_));
    exposed_index_ = -1;
  }
  const bool loop = loop_ && !exposed;  // a trigger's frame was wrapped by expose() already
  Read r = Read::kEnd;
  if (preload_) {
    if (frames_.empty()) return GrabStatus::kEndOfStream;
    if (next_index_ >= static_cast<int>(frames_.size()) && loop) next_index_ = 0;
    if (next_index_ < static_cast<int>(frames_.size())) {
      frame.image = frames_[static_cast<size_t>(next_index_++)];
      r = frame.image.empty() ? Read::kCorrupt : Read::kFrame;
    }
  } else if (exposed && next_index_ == prepared_index_) {
    std::swap(image_, prepared_);  // decoded while the node waited for this trigger
    prepared_index_ = -1;
    ++next_index_;
    r = Read::kFrame;
    frame.image = image_;
  } else {
    r = read_next(image_);
    if (r == Read::kEnd && loop && delivered_ > 0) {
      if (!pattern_) video_.set(cv::CAP_PROP_POS_FRAMES, 0);  // the start is a key frame
      next_index_ = 0;
      r = read_next(image_);
    }
    frame.image = image_;
  }
  if (r == Read::kEnd) return GrabStatus::kEndOfStream;
  if (r == Read::kCorrupt) {
    ++delivered_;  // the sensor's counter moves on: the frame existed, it is only unreadable
    return GrabStatus::kCorruptFrame;
  }
  frame.sequence = delivered_;
  frame.capture_utime =
      exposed
          ? exposed_utime_
          : t0_ + static_cast<int64_t>(std::llround(static_cast<double>(delivered_) * 1e6 / fps_));
  ++delivered_;
  return GrabStatus::kFrame;
}

void FileSource::stop() {
  video_.release();
  frames_.clear();
}

}  // namespace hullpose::camera_node
