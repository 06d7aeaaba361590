// The HTML report: one self-contained page, plots as inline SVG drawn here. Written by hand
// because no plotting library in Debian's C++ stack emits standalone SVG, and the plots
// needed (line series with gaps, shaded bands, Tukey box plots) are a few hundred lines.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "format.hpp"
#include "hullpose/common/check.hpp"
#include "hullpose/eval/report.hpp"
#include "hullpose/msg/reasons.hpp"

namespace hullpose::eval {
namespace {

namespace fs = std::filesystem;

std::string fmt(double v, int decimals = 1) {
  return fixed(v, decimals, "–");
}

std::string escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

struct Range {
  double lo, hi;
};

// Round tick positions (1, 2 or 5 times a power of ten) covering about `target` steps.
double tick_step(Range r, int target) {
  const double raw = (r.hi - r.lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  return (norm < 1.5 ? 1 : norm < 3 ? 2 : norm < 7 ? 5 : 10) * mag;
}

// [lo, hi] widened to whole ticks; a degenerate range gets some room.
Range nice_range(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {0, 1};
  if (hi - lo < 1e-9) {
    lo -= lo == 0 ? 0 : 1;
    hi += 1;
  }
  const double step = tick_step({lo, hi}, 5);
  return {std::floor(lo / step) * step, std::ceil(hi / step) * step};
}

// One plot: a data rectangle inside margins, with axes, grid, and the data marks in
// <g class="data"> (what the page's script checks for ink).
class SvgPlot {
 public:
  static constexpr double kLeft = 64, kRight = 16, kTop = 14, kBottom = 44;

  SvgPlot(double width, double height, Range x, Range y)
      : width_(width), height_(height), x_(x), y_(y) {}

  double px(double x) const {
    return kLeft + (x - x_.lo) / (x_.hi - x_.lo) * (width_ - kLeft - kRight);
  }
  double py(double y) const {
    return kTop + (y_.hi - y) / (y_.hi - y_.lo) * (height_ - kTop - kBottom);
  }
  double bottom() const { return height_ - kBottom; }

  void y_axis(const std::string& label) {
    const double step = tick_step(y_, 5);
    const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step))));
    for (double v = std::ceil(y_.lo / step) * step; v <= y_.hi + step * 1e-6; v += step) {
      const double y = py(v);
      back_ << "<line class='grid' x1='" << kLeft << "' x2='" << width_ - kRight << "' y1='" << y
            << "' y2='" << y << "'/><text class='tick' x='" << kLeft - 6 << "' y='" << y + 4
            << "' text-anchor='end'>" << fmt(v, decimals) << "</text>";
    }
    back_ << "<text class='label' transform='translate(16," << (kTop + bottom()) / 2
          << ") rotate(-90)' text-anchor='middle'>" << escape(label) << "</text>";
  }

  void x_axis_numeric(const std::string& label) {
    const double step = std::max(1.0, tick_step(x_, 10));
    for (double v = std::ceil(x_.lo / step) * step; v <= x_.hi + step * 1e-6; v += step)
      back_ << "<line class='tickmark' x1='" << px(v) << "' x2='" << px(v) << "' y1='" << bottom()
            << "' y2='" << bottom() + 5 << "'/><text class='tick' x='" << px(v) << "' y='"
            << bottom() + 18 << "' text-anchor='middle'>" << fmt(v, 0) << "</text>";
    back_ << "<text class='label' x='" << (kLeft + width_ - kRight) / 2 << "' y='" << height_ - 6
          << "' text-anchor='middle'>" << escape(label) << "</text>";
  }

  void x_axis_categories(const std::vector<std::string>& names) {
    for (size_t i = 0; i < names.size(); ++i) {
      const double x = px(static_cast<double>(i));
      back_ << "<text class='tick' transform='translate(" << x + 4 << "," << bottom() + 12
            << ") rotate(-40)' text-anchor='end'>" << escape(names[i]) << "</text>";
    }
  }

  // A shaded column over frames [x0, x1] (data units), behind the data.
  void band(double x0, double x1, const char* fill, const std::string& title) {
    back_ << "<rect x='" << px(x0) << "' y='" << kTop << "' width='"
          << std::max(1.0, px(x1) - px(x0)) << "' height='" << bottom() - kTop << "' fill='" << fill
          << "' fill-opacity='0.35'><title>" << escape(title) << "</title></rect>";
  }

  void hline(double y, const char* colour, const std::string& title) {
    front_ << "<line x1='" << kLeft << "' x2='" << width_ - kRight << "' y1='" << py(y) << "' y2='"
           << py(y) << "' stroke='" << colour << "' stroke-width='1' stroke-dasharray='5 4'><title>"
           << escape(title) << "</title></line>";
  }

  // A line through (xs[i], ys[i]); NaN values break it.
  void series(const std::vector<double>& xs, const std::vector<double>& ys, const char* colour,
              const std::string& title) {
    data_ << "<path fill='none' stroke='" << colour
          << "' stroke-width='2' stroke-linejoin='round' d='";
    bool pen_down = false;
    for (size_t i = 0; i < xs.size(); ++i) {
      if (!std::isfinite(ys[i])) {
        pen_down = false;
        continue;
      }
      // A lone point between gaps still needs ink: a zero-length segment with round caps.
      const bool lone = !pen_down && (i + 1 == xs.size() || !std::isfinite(ys[i + 1]));
      data_ << (pen_down ? 'L' : 'M') << fmt(px(xs[i]), 2) << ',' << fmt(py(ys[i]), 2) << ' ';
      if (lone) data_ << "l0.01,0 ";
      pen_down = true;
    }
    data_ << "' stroke-linecap='round'><title>" << escape(title) << "</title></path>";
  }

  std::ostream& data() { return data_; }

  // Lets the page's script map the pointer to a frame: data-hover names the readout, the rest
  // is the x mapping (data units lo..hi at viewBox x px0..px1).
  void hover(const std::string& readout) {
    std::ostringstream a;
    a << " data-hover='" << readout << "' data-lo='" << x_.lo << "' data-hi='" << x_.hi
      << "' data-px0='" << px(x_.lo) << "' data-px1='" << px(x_.hi) << "' data-top='" << kTop
      << "' data-bottom='" << bottom() << "'";
    attributes_ = a.str();
  }

  std::string svg(const std::string& id, const std::string& aria) const {
    std::ostringstream s;
    s << "<svg class='plot' id='" << id << "' viewBox='0 0 " << width_ << ' ' << height_
      << "' width='" << width_ << "' height='" << height_ << "' role='img' aria-label='"
      << escape(aria) << "'" << attributes_ << ">" << back_.str() << "<g class='data'>"
      << data_.str() << "</g>" << front_.str() << "<rect class='frame' x='" << kLeft << "' y='"
      << kTop << "' width='" << width_ - kLeft - kRight << "' height='" << bottom() - kTop
      << "'/></svg>";
    return s.str();
  }

 private:
  double width_, height_;
  Range x_, y_;
  std::ostringstream back_, data_, front_;
  std::string attributes_;
};

std::string legend(std::initializer_list<std::pair<const char*, std::string>> items,
                   bool swatch = false) {
  std::string s = "<div class='legend'>";
  for (const auto& [colour, text] : items)
    s += std::string("<span><i class='") + (swatch ? "sw" : "ln") +
         "' style='background:" + colour + "'></i>" + escape(text) + "</span>";
  return s + "</div>";
}

// Runs of consecutive frames for which pred holds, as [first, last] frame pairs.
template <typename Pred>
std::vector<std::pair<int, int>> runs(const std::vector<FrameResult>& frames, Pred pred) {
  std::vector<std::pair<int, int>> out;
  for (size_t i = 0; i < frames.size(); ++i) {
    if (!pred(frames[i])) continue;
    const bool extends =
        !out.empty() && i > 0 && pred(frames[i - 1]) && out.back().second == frames[i - 1].frame;
    if (extends)
      out.back().second = frames[i].frame;
    else
      out.emplace_back(frames[i].frame, frames[i].frame);
  }
  return out;
}

Range frame_range(const EvalResult& r) {
  const double first = r.per_frame.front().frame, last = r.per_frame.back().frame;
  return last > first ? Range{first - 0.5, last + 0.5} : Range{first - 1, first + 1};
}

std::string frame_span(std::pair<int, int> run) {
  return run.first == run.second
             ? "frame " + std::to_string(run.first)
             : "frames " + std::to_string(run.first) + "–" + std::to_string(run.second);
}

void shade_failures(SvgPlot& plot, const EvalResult& r) {
  for (const auto& run :
       runs(r.per_frame, [](const FrameResult& f) { return f.status == FrameStatus::Invalid; }))
    plot.band(run.first - 0.5, run.second + 0.5, colours::kInvalid,
              frame_span(run) + ": estimate invalid");
  for (const auto& run :
       runs(r.per_frame, [](const FrameResult& f) { return f.status == FrameStatus::Missing; }))
    plot.band(run.first - 0.5, run.second + 0.5, colours::kMissing,
              frame_span(run) + ": no estimate");
}

// Plot widths that fit the page's 1300 px column: full width, and half of it beside another
// section (minus padding, borders and the gap).
constexpr double kWide = 1266, kHalf = 608;

std::string per_frame_plot(const EvalResult& r) {
  std::vector<double> xs, all, hf;
  double top = 0;
  for (const FrameResult& f : r.per_frame) {
    xs.push_back(f.frame);
    all.push_back(f.mean_mm);
    hf.push_back(f.hands_feet_mm);
    if (f.status == FrameStatus::Scored) top = std::max({top, f.mean_mm, f.hands_feet_mm});
  }
  SvgPlot plot(kWide, 340, frame_range(r), nice_range(0, top));
  plot.y_axis("mean error (mm)");
  plot.x_axis_numeric("frame");
  shade_failures(plot, r);
  plot.hover("error");
  plot.series(xs, all, colours::kAllJoints, "mean error of all 25 joints");
  plot.series(xs, hf, colours::kHandsFeet, "mean error of hands and feet");
  if (std::isfinite(r.all_joints.mean))
    plot.hline(r.all_joints.mean, colours::kAllJoints, "MPJPE " + fmt(r.all_joints.mean) + " mm");
  return plot.svg("plot-frames", "mean joint error per frame");
}

// One coloured cell per frame: what happened to it, and for scored frames whether left and
// right came out the right way round.
std::string status_strip(const EvalResult& r) {
  const double height = 30;
  SvgPlot plot(kWide, height + SvgPlot::kTop + SvgPlot::kBottom, frame_range(r), {0, 1});
  plot.x_axis_numeric("frame");
  plot.hover("status");
  auto cls = [](const FrameResult& f) {
    if (f.status == FrameStatus::Invalid) return 2;
    if (f.status == FrameStatus::Missing) return 3;
    return f.lr_arms_correct && f.lr_legs_correct ? 0 : 1;
  };
  const char* fills[] = {colours::kLrCorrect, colours::kLrWrong, colours::kInvalid,
                         colours::kMissing};
  const char* what[] = {"left/right correct", "left/right swapped", "estimate invalid",
                        "no estimate"};
  for (int c = 0; c < 4; ++c)
    for (const auto& run : runs(r.per_frame, [&](const FrameResult& f) { return cls(f) == c; }))
      plot.data() << "<rect x='" << plot.px(run.first - 0.5) << "' y='" << SvgPlot::kTop
                  << "' width='"
                  << std::max(1.0, plot.px(run.second + 0.5) - plot.px(run.first - 0.5))
                  << "' height='" << height << "' fill='" << fills[c] << "'><title>"
                  << frame_span(run) << ": " << what[c] << "</title></rect>";
  return plot.svg("plot-status", "frame status");
}

std::string box_plot(const EvalResult& r) {
  double top = 0;
  for (const BoxStats& b : r.per_joint)
    if (b.count > 0) top = std::max(top, b.max);
  SvgPlot plot(kWide, 400, {-0.5, kNumJoints - 0.5}, nice_range(0, top));
  plot.y_axis("3D error (mm)");
  std::vector<std::string> names(kJointNames.begin(), kJointNames.end());
  plot.x_axis_categories(names);
  const double half = 0.32 * (plot.px(1) - plot.px(0));
  for (size_t j = 0; j < kNumJoints; ++j) {
    const BoxStats& b = r.per_joint[j];
    if (b.count == 0) continue;
    const Joint joint = static_cast<Joint>(j);
    const char* fill = mirror(joint) == joint     ? colours::kBoxCentre
                       : kJointNames[j][0] == 'L' ? colours::kBoxLeft
                                                  : colours::kBoxRight;
    const double x = plot.px(static_cast<double>(j));
    auto& d = plot.data();
    d << "<g class='box'><title>" << kJointNames[j] << ": median " << fmt(b.median) << " mm, box "
      << fmt(b.q1) << "–" << fmt(b.q3) << ", whiskers " << fmt(b.whisker_low) << "–"
      << fmt(b.whisker_high) << ", mean " << fmt(b.mean) << ", " << b.outliers.size()
      << " outliers</title>";
    d << "<line class='whisker' x1='" << x << "' x2='" << x << "' y1='" << plot.py(b.whisker_low)
      << "' y2='" << plot.py(b.q1) << "'/><line class='whisker' x1='" << x << "' x2='" << x
      << "' y1='" << plot.py(b.q3) << "' y2='" << plot.py(b.whisker_high) << "'/>";
    for (double w : {b.whisker_low, b.whisker_high})
      d << "<line class='whisker' x1='" << x - half / 2 << "' x2='" << x + half / 2 << "' y1='"
        << plot.py(w) << "' y2='" << plot.py(w) << "'/>";
    d << "<rect x='" << x - half << "' y='" << plot.py(b.q3) << "' width='" << 2 * half
      << "' height='" << std::max(1.5, plot.py(b.q1) - plot.py(b.q3)) << "' fill='" << fill
      << "' stroke='#334155' stroke-width='1'/>";
    d << "<line x1='" << x - half << "' x2='" << x + half << "' y1='" << plot.py(b.median)
      << "' y2='" << plot.py(b.median) << "' stroke='#0f172a' stroke-width='2.5'/>";
    d << "<path class='mean' d='M" << x - 4 << ',' << plot.py(b.mean) << " l4,-4 l4,4 l-4,4 z'/>";
    for (double o : b.outliers)
      d << "<circle class='outlier' cx='" << x << "' cy='" << plot.py(o) << "' r='2.5'/>";
    d << "</g>";
  }
  return plot.svg("plot-joints", "per-joint error box plots");
}

std::string axis_plot(const EvalResult& r, bool signed_error) {
  std::array<std::vector<double>, 3> ys;
  std::vector<double> xs;
  double lo = 0, hi = 0;
  for (const FrameResult& f : r.per_frame) {
    xs.push_back(f.frame);
    const Eigen::Vector3d& v = signed_error ? f.axis_bias_mm : f.axis_abs_mm;
    for (int a = 0; a < 3; ++a) {
      ys[static_cast<size_t>(a)].push_back(v[a]);
      if (std::isfinite(v[a])) {
        lo = std::min(lo, v[a]);
        hi = std::max(hi, v[a]);
      }
    }
  }
  SvgPlot plot(kHalf, 300, frame_range(r), nice_range(lo, hi));
  plot.y_axis(signed_error ? "mean signed error (mm)" : "mean |error| (mm)");
  plot.x_axis_numeric("frame");
  shade_failures(plot, r);
  plot.hover(signed_error ? "bias" : "abs");
  const char* axis_colours[] = {colours::kAxisX, colours::kAxisY, colours::kAxisZ};
  for (size_t a = 0; a < 3; ++a)
    plot.series(xs, ys[a], axis_colours[a], std::string(1, static_cast<char>('x' + a)) + " error");
  if (signed_error) plot.hline(0, "#475569", "zero");
  return plot.svg(signed_error ? "plot-axis-bias" : "plot-axis-abs",
                  signed_error ? "signed error per axis" : "absolute error per axis");
}

std::string card(const std::string& label, const std::string& value, const std::string& unit,
                 const std::string& note) {
  return "<div class='card'><div class='k'>" + escape(label) + "</div><div class='v'>" + value +
         "<small>" + unit + "</small></div><div class='n'>" + note + "</div></div>";
}

std::string joint_table(const EvalResult& r) {
  std::ostringstream t;
  t << "<table><thead><tr><th>joint</th><th>mean</th><th>std</th><th>median</th><th>q1</th>"
       "<th>q3</th><th>whiskers</th><th>max</th><th>outliers</th></tr></thead><tbody>";
  for (size_t j = 0; j < kNumJoints; ++j) {
    const BoxStats& b = r.per_joint[j];
    t << "<tr><td>" << kJointNames[j] << "</td><td>" << fmt(b.mean) << "</td><td>" << fmt(b.std)
      << "</td><td>" << fmt(b.median) << "</td><td>" << fmt(b.q1) << "</td><td>" << fmt(b.q3)
      << "</td><td>" << fmt(b.whisker_low) << "–" << fmt(b.whisker_high) << "</td><td>"
      << fmt(b.max) << "</td><td>" << b.outliers.size() << "</td></tr>";
  }
  t << "</tbody></table>";
  return t.str();
}

// The per-frame numbers for the pointer readout, as JSON arrays indexed like per_frame.
std::string frames_json(const EvalResult& r) {
  using Json = nlohmann::ordered_json;
  const auto num = [](double v) {
    return std::isfinite(v) ? Json(std::round(v * 10.0) / 10.0) : Json(nullptr);
  };
  const auto status = [](const FrameResult& f) -> std::string {
    if (f.status == FrameStatus::Scored)
      return f.lr_arms_correct && f.lr_legs_correct     ? "scored"
             : !f.lr_arms_correct && !f.lr_legs_correct ? "scored, arms and legs swapped"
             : !f.lr_arms_correct                       ? "scored, arms swapped"
                                                        : "scored, legs swapped";
    if (f.status == FrameStatus::Missing) return "missing from the estimate";
    return "invalid (" + msg::reason_name(f.reason) + ")";
  };
  Json j;
  for (const char* key :
       {"frame", "status", "all", "hf", "absx", "biasx", "absy", "biasy", "absz", "biasz"})
    j[key] = Json::array();
  for (const FrameResult& f : r.per_frame) {
    j["frame"].push_back(f.frame);
    j["status"].push_back(status(f));
    j["all"].push_back(num(f.mean_mm));
    j["hf"].push_back(num(f.hands_feet_mm));
    for (int a = 0; a < 3; ++a) {
      const char axis = static_cast<char>('x' + a);
      j[std::string("abs") + axis].push_back(num(f.axis_abs_mm[a]));
      j[std::string("bias") + axis].push_back(num(f.axis_bias_mm[a]));
    }
  }
  return j.dump();
}

constexpr const char* kStyle = R"CSS(
:root { --ink:#0f172a; --muted:#64748b; --line:#e2e8f0; }
* { box-sizing: border-box; }
body { margin: 0; background: #f8fafc; color: var(--ink);
       font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; }
main { width: 1348px; margin: 0 auto; padding: 20px 24px 40px; }
h1 { font-size: 22px; margin: 0 0 2px; }
h2 { font-size: 16px; margin: 0 0 4px; }
.src { color: var(--muted); font-size: 12.5px; word-break: break-all; }
.cards { display: grid; grid-template-columns: repeat(6, 1fr); gap: 10px; margin: 16px 0; }
.card { background: #fff; border: 1px solid var(--line); border-radius: 10px; padding: 10px 12px; }
.card .k { color: var(--muted); font-size: 12px; text-transform: uppercase; letter-spacing: .04em; }
.card .v { font-size: 24px; font-weight: 650; margin-top: 2px; }
.card .v small { font-size: 13px; font-weight: 500; color: var(--muted); margin-left: 3px; }
.card .n { color: var(--muted); font-size: 12px; }
section { background: #fff; border: 1px solid var(--line); border-radius: 10px; padding: 14px 16px;
          margin-bottom: 14px; }
.row { display: flex; gap: 14px; }
.row section { flex: 1; }
.note { color: var(--muted); font-size: 12.5px; margin: 0 0 6px; }
.legend { display: flex; flex-wrap: wrap; gap: 16px; font-size: 12.5px; margin: 2px 0 6px; }
.legend i { display: inline-block; vertical-align: middle; margin-right: 6px; }
.legend i.ln { width: 18px; height: 3px; border-radius: 2px; }
.legend i.sw { width: 12px; height: 12px; border-radius: 3px; }
svg.plot { display: block; }
svg .grid { stroke: #eef2f7; stroke-width: 1; }
svg .frame { fill: none; stroke: #cbd5e1; stroke-width: 1; }
svg .tickmark { stroke: #94a3b8; }
svg .tick { fill: #475569; font-size: 11px; }
svg .label { fill: #334155; font-size: 12px; }
svg .whisker { stroke: #334155; stroke-width: 1.2; }
svg .mean { fill: #0f172a; }
svg .outlier { fill: none; stroke: #64748b; stroke-width: 1; }
table { border-collapse: collapse; width: 100%; font-size: 12.5px; font-variant-numeric: tabular-nums; }
th, td { padding: 3px 8px; text-align: right; border-bottom: 1px solid var(--line); }
th:first-child, td:first-child { text-align: left; }
th { color: var(--muted); font-weight: 600; }
dl { display: grid; grid-template-columns: 210px 1fr; gap: 4px 14px; margin: 0; font-size: 13px; }
dt { font-weight: 600; }
dd { margin: 0; color: #334155; }
#tip { position: fixed; pointer-events: none; display: none; background: rgba(15,23,42,.92); color: #f8fafc;
       font-size: 12px; padding: 6px 9px; border-radius: 6px; white-space: nowrap; z-index: 10; }
#tip b { font-weight: 650; }
svg .cursor { stroke: #0f172a; stroke-width: 1; stroke-opacity: .45; pointer-events: none; }
)CSS";

// Marks the page once the browser has laid the plots out, so a headless check can tell a
// drawn report from an empty one: body[data-plots-drawn] = "<plots with ink>/<plots>".
constexpr const char* kScript = R"JS(
(function () {
  var plots = document.querySelectorAll('svg.plot'), drawn = 0;
  plots.forEach(function (svg) {
    var g = svg.querySelector('g.data'), box = g ? g.getBBox() : null;
    if (box && box.width > 0 && box.height > 0) drawn++;
  });
  document.body.setAttribute('data-plots-drawn', drawn + '/' + plots.length);
})();
// Pointer readout: the nearest frame's numbers under the cursor.
(function () {
  var data = JSON.parse(document.getElementById('frame-data').textContent);
  var tip = document.getElementById('tip'), NS = 'http://www.w3.org/2000/svg';
  function mm(v) { return v === null ? '–' : v.toFixed(1) + ' mm'; }
  function lines(kind, i) {
    if (kind === 'error') return ['all joints ' + mm(data.all[i]), 'hands + feet ' + mm(data.hf[i])];
    if (kind === 'abs') return ['|x| ' + mm(data.absx[i]), '|y| ' + mm(data.absy[i]), '|z| ' + mm(data.absz[i])];
    if (kind === 'bias') return ['x ' + mm(data.biasx[i]), 'y ' + mm(data.biasy[i]), 'z ' + mm(data.biasz[i])];
    return [];
  }
  document.querySelectorAll('svg[data-hover]').forEach(function (svg) {
    var d = svg.dataset, lo = +d.lo, hi = +d.hi, px0 = +d.px0, px1 = +d.px1;
    var cursor = document.createElementNS(NS, 'line');
    cursor.setAttribute('class', 'cursor');
    cursor.setAttribute('y1', d.top);
    cursor.setAttribute('y2', d.bottom);
    cursor.style.display = 'none';
    svg.appendChild(cursor);
    svg.addEventListener('mousemove', function (e) {
      var p = svg.createSVGPoint();
      p.x = e.clientX; p.y = e.clientY;
      p = p.matrixTransform(svg.getScreenCTM().inverse());
      var f = lo + (p.x - px0) / (px1 - px0) * (hi - lo), a = 0, b = data.frame.length - 1;
      while (b - a > 1) { var m = (a + b) >> 1; if (data.frame[m] <= f) a = m; else b = m; }
      var i = Math.abs(data.frame[b] - f) < Math.abs(data.frame[a] - f) ? b : a;
      var x = px0 + (data.frame[i] - lo) / (hi - lo) * (px1 - px0);
      cursor.setAttribute('x1', x); cursor.setAttribute('x2', x);
      cursor.style.display = '';
      tip.innerHTML = '<b>frame ' + data.frame[i] + '</b> · ' + data.status[i] +
                      lines(d.hover, i).map(function (l) { return '<br>' + l; }).join('');
      tip.style.display = 'block';
      tip.style.left = Math.min(e.clientX + 14, window.innerWidth - tip.offsetWidth - 8) + 'px';
      tip.style.top = (e.clientY + 14) + 'px';
    });
    svg.addEventListener('mouseleave', function () { cursor.style.display = 'none'; tip.style.display = 'none'; });
  });
})();
)JS";

}  // namespace

fs::path write_html_report(const fs::path& dir, const EvalResult& r, const ReportSource& source) {
  HULLPOSE_ASSERT(!r.per_frame.empty());
  std::error_code ec;
  fs::create_directories(dir, ec);
  HULLPOSE_THROW_UNLESS(!ec && fs::is_directory(dir), dir.string()
                                                          << ": cannot create report directory"
                                                          << (ec ? ": " + ec.message() : ""));
  const fs::path path = dir / "report.html";
  std::ofstream out(path);
  HULLPOSE_THROW_UNLESS(out, path.string() << ": cannot write");

  std::string reasons;
  for (const auto& [code, count] : r.invalid_reasons)
    reasons += (reasons.empty() ? "" : ", ") + msg::reason_name(code) + " " + std::to_string(count);

  out << "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>hullpose-eval: "
      << escape(source.motion.empty() ? source.dataset : source.motion) << "</title><style>"
      << kStyle << "</style></head><body><main>";
  out << "<h1>Pose estimate vs ground truth"
      << (source.motion.empty() ? "" : " — " + escape(source.motion))
      << "</h1><div class='src'>estimate " << escape(source.estimate) << " · ground truth "
      << escape(source.dataset) << "</div>";

  out << "<div class='cards'>"
      << card("MPJPE", fmt(r.all_joints.mean), "mm",
              "std " + fmt(r.all_joints.std) + " · median " + fmt(r.all_joints.median))
      << card("Hands + feet", fmt(r.hands_feet.mean), "mm",
              "std " + fmt(r.hands_feet.std) + " · with head " + fmt(r.extremities.mean))
      << card("PCK @100 mm", fmt(r.pck100_pct), "%",
              "@50 mm " + fmt(r.pck50_pct) + " % · all frames")
      << card("Valid frames", fmt(r.valid_pct), "%",
              std::to_string(r.scored_frames) + " of " + std::to_string(r.frames) + " · " +
                  std::to_string(r.invalid_frames) + " invalid · " +
                  std::to_string(r.missing_frames) + " missing")
      << card("Left/right correct", fmt(r.lr_correct_pct), "%",
              "arms " + fmt(r.lr_arms_correct_pct) + " · legs " + fmt(r.lr_legs_correct_pct))
      << card("Stature error", fmt(r.stature_error_mm), "mm",
              "est " + fmt(r.stature_est_mm, 0) + " · true " + fmt(r.stature_meta_mm, 0))
      << "</div>";

  out << "<section><h2>Error per frame</h2><p class='note'>Mean Euclidean distance between "
         "estimated "
         "and true joints in each frame (cf. thesis Fig. 6.1). Frames the estimator marked invalid "
         "or did not deliver are shaded, not drawn as zero.</p>"
      << legend({{colours::kAllJoints, "all 25 joints"},
                 {colours::kHandsFeet, "hands and feet"},
                 {colours::kInvalid, "invalid" + (reasons.empty() ? "" : " (" + reasons + ")")},
                 {colours::kMissing, "missing"}})
      << per_frame_plot(r) << "<p class='note' style='margin-top:8px'>Frame status</p>"
      << legend({{colours::kLrCorrect, "left/right correct"},
                 {colours::kLrWrong, "left/right swapped"},
                 {colours::kInvalid, "invalid"},
                 {colours::kMissing, "missing"}},
                true)
      << status_strip(r) << "</section>";

  out << "<section><h2>Error per joint</h2><p class='note'>Box: quartiles, bar: median, diamond: "
         "mean, whiskers: furthest samples within 1.5 IQR of the box, circles: outliers (cf. "
         "thesis "
         "Fig. 6.4). Scored frames only.</p>"
      << legend({{colours::kBoxLeft, "left"},
                 {colours::kBoxRight, "right"},
                 {colours::kBoxCentre, "centre"}},
                true)
      << box_plot(r) << "</section>";

  out << "<div class='row'><section><h2>Absolute error per axis</h2><p class='note'>Mean |estimate "
         "− "
         "truth| over the joints, per rig axis (z up).</p>"
      << legend({{colours::kAxisX, "x"}, {colours::kAxisY, "y"}, {colours::kAxisZ, "z"}})
      << axis_plot(r, false)
      << "</section><section><h2>Signed error per axis</h2><p class='note'>Mean (estimate − "
         "truth): "
         "a systematic offset shows as a level away from zero.</p>"
      << legend({{colours::kAxisX, "x"}, {colours::kAxisY, "y"}, {colours::kAxisZ, "z"}})
      << axis_plot(r, true) << "</section></div>";

  out << "<div class='row'><section><h2>Per joint (mm)</h2>" << joint_table(r)
      << "</section><section><h2>Definitions</h2><dl>"
      << "<dt>Scored frame</dt><dd>a ground-truth frame the estimate delivered with valid=1. All "
         "errors, left/right and stature figures are over scored frames.</dd>"
      << "<dt>Invalid / missing</dt><dd>valid=0 rows, and ground-truth frames with no estimate "
         "row. "
         "They count against valid % and PCK (all frames), never as zero error.</dd>"
      << "<dt>PCK @d</dt><dd>% of (frame, joint) pairs within d mm of the truth; “all frames” "
         "counts invalid and missing frames as misses (scored frames only: "
      << fmt(r.pck50_valid_pct) << " % / " << fmt(r.pck100_valid_pct) << " %).</dd>"
      << "<dt>Left/right correct</dt><dd>for arms (shoulder…finger tip) and legs (hip…toe): the "
         "summed joint distances with sides as labelled are no larger than with left and right "
         "exchanged; a frame is correct when both are.</dd>"
      << "<dt>Stature</dt><dd>least-squares S with bone length = ratio × S over the 24 bones "
         "(thesis Table 6.7), of estimate and ground truth per frame. Error = estimate − ground "
         "truth: "
      << fmt(r.stature_est_mm) << " − " << fmt(r.stature_gt_mm) << " mm; vs the true stature "
      << fmt(r.stature_meta_mm) << " mm: " << fmt(r.stature_error_meta_mm) << " mm.</dd>"
      << "<dt>Axis error</dt><dd>x " << fmt(r.axis_abs_mm.x()) << ", y " << fmt(r.axis_abs_mm.y())
      << ", z " << fmt(r.axis_abs_mm.z()) << " mm mean |error|; bias x " << fmt(r.axis_bias_mm.x())
      << ", y " << fmt(r.axis_bias_mm.y()) << ", z " << fmt(r.axis_bias_mm.z()) << " mm.</dd>"
      << "</dl></section></div>";

  out << "</main><div id='tip'></div><script type='application/json' id='frame-data'>"
      << frames_json(r) << "</script><script>" << kScript << "</script></body></html>\n";
  HULLPOSE_THROW_UNLESS(out, path.string() << ": write failed");
  return path;
}

}  // namespace hullpose::eval
