#include "hullpose/skeleton_io/markers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <string>
#include <vector>

#include "hullpose/common/check.hpp"

namespace hullpose::skeleton_io {
namespace {

Eigen::Vector3d y_up(const Eigen::Vector3d& p) {
  return {p.x(), p.z(), -p.y()};
}

// C3D, Intel byte order (processor type 84): 16-bit words and IEEE floats, little-endian.
class C3dBuffer {
 public:
  void u8(int v) { bytes_.push_back(static_cast<unsigned char>(v & 0xFF)); }
  void i16(int v) {
    u8(v);
    u8(v >> 8);
  }
  void f32(float v) {
    unsigned char b[4];
    std::memcpy(b, &v, 4);  // x86 and ARM Linux are little-endian, as processor type 84 says
    bytes_.insert(bytes_.end(), b, b + 4);
  }
  void text(const std::string& s) { bytes_.insert(bytes_.end(), s.begin(), s.end()); }
  size_t size() const { return bytes_.size(); }
  void pad_to_block() { bytes_.resize((bytes_.size() + 511) / 512 * 512, 0); }
  void put_u8(size_t at, int v) { bytes_[at] = static_cast<unsigned char>(v & 0xFF); }
  void put_i16(size_t at, int v) {
    bytes_[at] = static_cast<unsigned char>(v & 0xFF);
    bytes_[at + 1] = static_cast<unsigned char>((v >> 8) & 0xFF);
  }
  void put_f32(size_t at, float v) { std::memcpy(&bytes_[at], &v, 4); }
  const std::vector<unsigned char>& bytes() const { return bytes_; }

 private:
  std::vector<unsigned char> bytes_;
};

// The parameter section's records (c3d.org: Group Format, Parameter Format). Each record's
// "next" field is the byte count from that field to the next record; the last one holds 0.
class C3dParameters {
 public:
  explicit C3dParameters(C3dBuffer& out) : out_(out) {}
  void group(int id, const std::string& name, const std::string& description) {
    begin(name, -id);
    out_.u8(static_cast<int>(description.size()));
    out_.text(description);
  }
  // type: -1 char, 2 int16, 4 float; dims in FORTRAN order (fastest first); data as raw bytes.
  template <typename Fill>
  void parameter(int group, const std::string& name, int type, const std::vector<int>& dims,
                 Fill fill, const std::string& description) {
    begin(name, group);
    out_.u8(type);
    out_.u8(static_cast<int>(dims.size()));
    for (int d : dims) out_.u8(d);
    fill();
    out_.u8(static_cast<int>(description.size()));
    out_.text(description);
  }
  void int16(int group, const std::string& name, int value, const std::string& description) {
    parameter(
        group, name, 2, {}, [&] { out_.i16(value); }, description);
  }
  void real(int group, const std::string& name, float value, const std::string& description) {
    parameter(
        group, name, 4, {}, [&] { out_.f32(value); }, description);
  }
  void chars(int group, const std::string& name, const std::string& value,
             const std::string& description) {
    parameter(
        group, name, -1, {static_cast<int>(value.size())}, [&] { out_.text(value); }, description);
  }
  void strings(int group, const std::string& name, const std::vector<std::string>& values,
               const std::string& description) {
    size_t width = 1;
    for (const auto& v : values) width = std::max(width, v.size());
    parameter(
        group, name, -1, {static_cast<int>(width), static_cast<int>(values.size())},
        [&] {
          for (const auto& v : values) out_.text(v + std::string(width - v.size(), ' '));
        },
        description);
  }
  void finish() {
    if (last_next_ != 0) out_.put_i16(last_next_, 0);
  }

 private:
  void begin(const std::string& name, int id) {
    if (last_next_ != 0) out_.put_i16(last_next_, static_cast<int>(out_.size() - last_next_));
    out_.u8(static_cast<int>(name.size()));
    out_.u8(id);
    out_.text(name);
    last_next_ = out_.size();
    out_.i16(0);
  }
  C3dBuffer& out_;
  size_t last_next_ = 0;
};

void write_file(const std::filesystem::path& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary);
  HULLPOSE_THROW_UNLESS(out.good(), path.string() << ": cannot write");
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  HULLPOSE_THROW_UNLESS(out.good(), path.string() << ": write failed");
}

}  // namespace

void write_trc(const std::filesystem::path& path, const Take& take, const GapReport& gaps) {
  std::ofstream out(path);
  HULLPOSE_THROW_UNLESS(out.good(), path.string() << ": cannot write");
  const size_t n = take.frames.size();
  out << "PathFileType\t4\t(X/Y/Z)\t" << path.filename().string() << "\n";
  out << "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOri"
         "gNumFrames\n";
  out << std::fixed << std::setprecision(6) << take.fps << '\t' << take.fps << '\t' << n << '\t'
      << kNumJoints << "\tmm\t" << take.fps << "\t1\t" << n << "\n";
  out << "Frame#\tTime";
  for (auto name : kJointNames) out << '\t' << name << "\t\t";
  out << "\n\t";
  for (int j = 1; j <= kNumJoints; ++j) out << "\tX" << j << "\tY" << j << "\tZ" << j;
  out << "\n\n";
  for (size_t f = 0; f < n; ++f) {
    out << f + 1 << '\t' << std::setprecision(6) << static_cast<double>(f) / take.fps
        << std::setprecision(3);
    const bool missing = gaps.state[f] == FrameState::Missing;
    for (const Eigen::Vector3d& p : take.frames[f].joints) {
      if (missing) {
        out << "\t\t\t";
        continue;
      }
      const Eigen::Vector3d q = y_up(p);
      out << '\t' << q.x() << '\t' << q.y() << '\t' << q.z();
    }
    out << '\n';
  }
  HULLPOSE_THROW_UNLESS(out.good(), path.string() << ": write failed");
}

void write_c3d(const std::filesystem::path& path, const Take& take, const GapReport& gaps) {
  const size_t n = take.frames.size();
  HULLPOSE_THROW_UNLESS(
      n >= 1 && n <= 65535,
      path.string() << ": C3D holds 1..65535 frames in its 16-bit counts, the take has " << n);
  double max_abs = 1;
  for (size_t f = 0; f < n; ++f)
    if (gaps.state[f] != FrameState::Missing)
      for (const Eigen::Vector3d& p : take.frames[f].joints)
        max_abs = std::max(max_abs, p.cwiseAbs().maxCoeff());
  // Negative SCALE: the data are floats; its size still gives the residual unit (max / 32000).
  const float scale = -static_cast<float>(max_abs / 32000.0);
  const float rate = static_cast<float>(take.fps);
  int max_gap = 0;
  for (size_t f = 0, run = 0; f < n; ++f) {
    run = gaps.state[f] == FrameState::Filled ? run + 1 : 0;
    max_gap = std::max(max_gap, static_cast<int>(run));
  }

  C3dBuffer c3d;
  // Header section: block 1 (c3d.org, "The C3D file header record"; words are 1-based there).
  c3d.u8(2);                     // word 1: parameter section starts at block 2
  c3d.u8(0x50);                  // ... and the data are 3D points
  c3d.i16(kNumJoints);           // word 2: points per frame
  c3d.i16(0);                    // word 3: analog measurements per frame
  c3d.i16(1);                    // word 4: first frame
  c3d.i16(static_cast<int>(n));  // word 5: last frame
  c3d.i16(max_gap);              // word 6: largest interpolated gap
  c3d.f32(scale);                // words 7-8
  const size_t header_data_start = c3d.size();
  c3d.i16(0);     // word 9: DATA_START, patched below
  c3d.i16(0);     // word 10: analog samples per frame
  c3d.f32(rate);  // words 11-12
  c3d.pad_to_block();
  c3d.put_i16(2 * (150 - 1), 0x3039);  // word 150: 4-character event labels (none stored)

  // Parameter section: block 2 on.
  const size_t param_start = c3d.size();
  c3d.u8(1);
  c3d.u8(0x50);
  c3d.u8(0);   // number of parameter blocks, patched below
  c3d.u8(84);  // processor type: Intel
  C3dParameters p(c3d);
  p.group(1, "POINT", "3D points: the 25 joints of the hullpose model");
  p.int16(1, "USED", kNumJoints, "number of points per frame");
  p.int16(1, "FRAMES", static_cast<int>(n), "number of frames");
  size_t data_start_value = 0;
  p.parameter(
      1, "DATA_START", 2, {},
      [&] {
        data_start_value = c3d.size();
        c3d.i16(0);
      },
      "first block of the 3D data");
  p.real(1, "SCALE", scale, "negative: floating-point data");
  p.real(1, "RATE", rate, "frames per second");
  p.chars(1, "UNITS", "mm", "units of the point coordinates");
  std::vector<std::string> labels(kJointNames.begin(), kJointNames.end());
  p.strings(1, "LABELS", labels, "joint names (hullpose common/joints.hpp)");
  p.strings(1, "DESCRIPTIONS", labels, "joint names");
  p.chars(1, "X_SCREEN", "+X", "horizontal screen axis");
  p.chars(1, "Y_SCREEN", "+Y", "vertical screen axis: Y up");
  p.group(2, "ANALOG", "no analog channels");
  p.int16(2, "USED", 0, "analog channels");
  p.real(2, "RATE", rate, "no analog data: the point rate");
  p.group(3, "MANUFACTURER", "who wrote this file");
  p.chars(3, "COMPANY", "hullpose", "project");
  p.chars(3, "SOFTWARE", "hullpose-export", "program");
  p.finish();
  c3d.pad_to_block();
  const size_t param_blocks = (c3d.size() - param_start) / 512;
  HULLPOSE_ASSERT(param_blocks >= 1 && param_blocks <= 255);
  const int data_start = static_cast<int>(c3d.size() / 512 + 1);
  c3d.put_u8(param_start + 2, static_cast<int>(param_blocks));
  c3d.put_i16(header_data_start, data_start);
  c3d.put_i16(data_start_value, data_start);

  // Data section: per frame, per point X Y Z and the residual word (c3d.org, 3D Data -
  // Floating-point Format): -1 missing, 0 interpolated, else camera mask (high byte, cameras 1-7)
  // and residual 1 (our fit gives no per-point residual; a positive one says "measured").
  for (size_t f = 0; f < n; ++f) {
    const SkeletonFrame& frame = take.frames[f];
    const FrameState state = gaps.state[f];
    const int cameras = static_cast<int>(frame.cameras_used_mask & 0x7F);
    for (const Eigen::Vector3d& pos : frame.joints) {
      const Eigen::Vector3d q = state == FrameState::Missing ? Eigen::Vector3d::Zero() : y_up(pos);
      c3d.f32(static_cast<float>(q.x()));
      c3d.f32(static_cast<float>(q.y()));
      c3d.f32(static_cast<float>(q.z()));
      c3d.f32(state == FrameState::Missing  ? -1.f
              : state == FrameState::Filled ? 0.f
                                            : static_cast<float>(cameras << 8 | 1));
    }
  }
  c3d.pad_to_block();
  write_file(path, c3d.bytes().data(), c3d.size());
}

}  // namespace hullpose::skeleton_io
