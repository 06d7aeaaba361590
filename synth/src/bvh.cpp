#include "hullpose/synth/bvh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "hullpose/common/check.hpp"

namespace hullpose::synth {
namespace {

struct Token {
  std::string_view text;
  int line;
};

// Splits on any whitespace; '\r' counts as whitespace, so CRLF, LF and mixed files read alike.
class Lexer {
 public:
  Lexer(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  bool at_end() {
    skip_space();
    return pos_ >= text_.size();
  }
  Token next(const char* expecting) {
    skip_space();
    HULLPOSE_THROW_UNLESS(pos_ < text_.size(), source_ << ":" << line_
                                                       << ": unexpected end of file, expecting "
                                                       << expecting);
    const size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return {text_.substr(start, pos_ - start), line_};
  }
  void expect(std::string_view word) {
    const Token t = next(std::string(word).c_str());
    HULLPOSE_THROW_UNLESS(t.text == word, source_ << ":" << t.line << ": expected '" << word
                                                  << "', found '" << t.text << "'");
  }
  double number(const char* what) {
    const Token t = next(what);
    return parse(t, what);
  }
  double parse(const Token& t, const std::string& what) const {
    double v = 0;
    const auto [end, ec] = std::from_chars(t.text.data(), t.text.data() + t.text.size(), v);
    HULLPOSE_THROW_UNLESS(
        ec == std::errc() && end == t.text.data() + t.text.size(),
        source_ << ":" << t.line << ": " << what << ": '" << t.text << "' is not a number");
    HULLPOSE_THROW_UNLESS(std::isfinite(v), source_ << ":" << t.line << ": " << what
                                                    << " is not finite ('" << t.text << "')");
    return v;
  }
  // The rest of the current line (for the motion section, which is line-oriented).
  bool next_line(std::string_view& line, int& line_no) {
    if (pos_ >= text_.size()) return false;
    const size_t nl = text_.find('\n', pos_);
    const size_t end = nl == std::string_view::npos ? text_.size() : nl;
    line = text_.substr(pos_, end - pos_);
    line_no = line_;
    pos_ = nl == std::string_view::npos ? text_.size() : nl + 1;
    if (nl != std::string_view::npos) ++line_;
    return true;
  }
  // Moves to the start of the next line (after a header token such as "Frame Time: x").
  void finish_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') {
      HULLPOSE_THROW_UNLESS(is_space(text_[pos_]),
                            source_ << ":" << line_ << ": unexpected text after the header value");
      ++pos_;
    }
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
  }
  const std::string& source() const { return source_; }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  std::string_view text_;
  const std::string& source_;
  size_t pos_ = 0;
  int line_ = 1;
};

BvhChannel channel_from(const Token& t, const std::string& joint, const std::string& source) {
  static constexpr std::pair<std::string_view, BvhChannel> kNames[] = {
      {"Xposition", BvhChannel::Xposition}, {"Yposition", BvhChannel::Yposition},
      {"Zposition", BvhChannel::Zposition}, {"Xrotation", BvhChannel::Xrotation},
      {"Yrotation", BvhChannel::Yrotation}, {"Zrotation", BvhChannel::Zrotation}};
  for (const auto& [name, ch] : kNames)
    if (t.text == name) return ch;
  HULLPOSE_THROW(source << ":" << t.line << ": unknown channel '" << t.text << "' of joint "
                        << joint);
}

const char* channel_name(BvhChannel c) {
  switch (c) {
    case BvhChannel::Xposition:
      return "Xposition";
    case BvhChannel::Yposition:
      return "Yposition";
    case BvhChannel::Zposition:
      return "Zposition";
    case BvhChannel::Xrotation:
      return "Xrotation";
    case BvhChannel::Yrotation:
      return "Yrotation";
    case BvhChannel::Zrotation:
      return "Zrotation";
  }
  return "?";
}

// Parses "{ OFFSET ... [CHANNELS ...] (JOINT ...| End Site ...)* }" for the joint just named.
void parse_joint(Lexer& lx, BvhClip& clip, const std::string& name, int parent, int line,
                 bool end_site, int depth) {
  HULLPOSE_THROW_UNLESS(depth < 256, lx.source() << ":" << line << ": hierarchy nested too deeply");
  const int index = static_cast<int>(clip.joints.size());
  clip.joints.push_back({name, parent, Eigen::Vector3d::Zero(), {}, clip.channel_count, line});
  lx.expect("{");
  lx.expect("OFFSET");
  Eigen::Vector3d offset;
  for (int i = 0; i < 3; ++i) offset[i] = lx.number(("OFFSET of joint " + name).c_str());
  clip.joints[static_cast<size_t>(index)].offset = offset;
  while (true) {
    const Token t = lx.next("'}', CHANNELS, JOINT or End Site");
    if (t.text == "}") return;
    if (t.text == "CHANNELS") {
      HULLPOSE_THROW_UNLESS(!end_site, lx.source() << ":" << t.line << ": End Site of " << name
                                                   << " cannot have channels");
      const double n = lx.number(("channel count of joint " + name).c_str());
      HULLPOSE_THROW_UNLESS(n >= 0 && n <= 6 && n == std::floor(n),
                            lx.source() << ":" << t.line << ": joint " << name << ": channel count "
                                        << n << " must be 0..6");
      auto& joint = clip.joints[static_cast<size_t>(index)];
      joint.first_channel = clip.channel_count;
      for (int i = 0; i < static_cast<int>(n); ++i)
        joint.channels.push_back(channel_from(lx.next("a channel name"), name, lx.source()));
      clip.channel_count += static_cast<int>(n);
    } else if (t.text == "JOINT") {
      HULLPOSE_THROW_UNLESS(!end_site, lx.source()
                                           << ":" << t.line << ": End Site cannot have children");
      const Token child = lx.next("a joint name");
      parse_joint(lx, clip, std::string(child.text), index, child.line, false, depth + 1);
    } else if (t.text == "End") {
      lx.expect("Site");
      parse_joint(lx, clip, name + "_End", index, t.line, true, depth + 1);
    } else {
      HULLPOSE_THROW(lx.source() << ":" << t.line << ": unexpected '" << t.text << "' in joint "
                                 << name);
    }
  }
}

}  // namespace

int BvhClip::find(std::string_view name) const {
  for (size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == name) return static_cast<int>(i);
  return -1;
}

void BvhClip::forward_kinematics(int frame, std::vector<Eigen::Matrix3d>& rotation,
                                 std::vector<Eigen::Vector3d>& position) const {
  HULLPOSE_ASSERT(frame >= -1 && frame < frames);
  rotation.resize(joints.size());
  position.resize(joints.size());
  const double* row = frame >= 0
                          ? &motion[static_cast<size_t>(frame) * static_cast<size_t>(channel_count)]
                          : nullptr;
  for (size_t i = 0; i < joints.size(); ++i) {
    const BvhJoint& j = joints[i];
    Eigen::Matrix3d local = Eigen::Matrix3d::Identity();
    Eigen::Vector3d translation = j.offset;
    if (row) {
      for (size_t c = 0; c < j.channels.size(); ++c) {
        const double v = row[j.first_channel + static_cast<int>(c)];
        const double rad = v * M_PI / 180.0;
        switch (j.channels[c]) {
          case BvhChannel::Xposition:
            translation.x() += v;
            break;
          case BvhChannel::Yposition:
            translation.y() += v;
            break;
          case BvhChannel::Zposition:
            translation.z() += v;
            break;
          // Rotations compose in the listed order (intrinsic): ZYX gives Rz * Ry * Rx.
          case BvhChannel::Xrotation:
            local = local * Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitX());
            break;
          case BvhChannel::Yrotation:
            local = local * Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitY());
            break;
          case BvhChannel::Zrotation:
            local = local * Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitZ());
            break;
        }
      }
    }
    if (j.parent < 0) {
      rotation[i] = local;
      position[i] = translation;
    } else {
      const auto p = static_cast<size_t>(j.parent);
      rotation[i] = rotation[p] * local;
      position[i] = position[p] + rotation[p] * translation;
    }
  }
}

BvhClip parse_bvh(std::string_view text, const std::string& source) {
  Lexer lx(text, source);
  BvhClip clip;
  clip.source = source;
  lx.expect("HIERARCHY");
  lx.expect("ROOT");
  const Token root = lx.next("the root joint name");
  parse_joint(lx, clip, std::string(root.text), -1, root.line, false, 0);
  HULLPOSE_THROW_UNLESS(clip.channel_count > 0, source << ": the hierarchy declares no channels");
  lx.expect("MOTION");
  lx.expect("Frames:");
  const Token frames_tok = lx.next("the frame count");
  const double frames = lx.parse(frames_tok, "frame count");
  HULLPOSE_THROW_UNLESS(frames >= 1 && frames <= 10'000'000 && frames == std::floor(frames),
                        source << ":" << frames_tok.line << ": frame count " << frames_tok.text
                               << " must be a positive integer");
  lx.expect("Frame");
  lx.expect("Time:");
  const Token ft = lx.next("the frame time");
  clip.frame_time_s = lx.parse(ft, "frame time");
  HULLPOSE_THROW_UNLESS(
      clip.frame_time_s > 1e-5 && clip.frame_time_s < 10,
      source << ":" << ft.line << ": frame time " << ft.text << " s is out of range");
  lx.finish_line();
  clip.frames = static_cast<int>(frames);

  // Which joint owns each column, to name it when a value is bad or missing.
  std::vector<std::pair<const BvhJoint*, BvhChannel>> owner;
  for (const auto& j : clip.joints)
    for (BvhChannel c : j.channels) owner.emplace_back(&j, c);

  // Every value takes at least two bytes of text: a lying frame count cannot reserve more.
  clip.motion.reserve(std::min(
      static_cast<size_t>(clip.frames) * static_cast<size_t>(clip.channel_count), text.size() / 2));
  std::string_view line;
  int line_no = 0;
  int read = 0;
  while (read < clip.frames && lx.next_line(line, line_no)) {
    Lexer ll(line, source);
    if (ll.at_end()) continue;  // blank line
    for (int c = 0; c < clip.channel_count; ++c) {
      const auto& [joint, channel] = owner[static_cast<size_t>(c)];
      const std::string what = "frame " + std::to_string(read + 1) + ", joint " + joint->name +
                               " " + channel_name(channel);
      HULLPOSE_THROW_UNLESS(!ll.at_end(), source << ":" << line_no << ": " << what
                                                 << ": value missing (line has " << c << " of "
                                                 << clip.channel_count << " values)");
      Token t = ll.next("a value");
      t.line = line_no;
      clip.motion.push_back(ll.parse(t, what));
    }
    HULLPOSE_THROW_UNLESS(ll.at_end(), source << ":" << line_no << ": more than "
                                              << clip.channel_count << " values on a motion line");
    ++read;
  }
  HULLPOSE_THROW_UNLESS(read == clip.frames,
                        source << ":" << line_no << ": truncated motion: the header says "
                               << clip.frames << " frames, the file holds " << read);
  HULLPOSE_THROW_UNLESS(lx.at_end(),
                        source << ": text after the last of " << clip.frames << " motion frames");
  return clip;
}

BvhClip load_bvh(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  HULLPOSE_THROW_UNLESS(in, path.string() << ": cannot open BVH file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_bvh(ss.str(), path.string());
}

}  // namespace hullpose::synth
