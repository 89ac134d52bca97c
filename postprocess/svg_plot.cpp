#include "svg_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace freestand::svg {

namespace {

constexpr double kFontSize = 12;       // tick labels, legend
constexpr double kTitleSize = 14;
constexpr double kSmallSize = 10;      // labels above the frame
constexpr double kEm = 0.62;           // mean advance of DejaVu Sans / Liberation Sans, in em
constexpr double kLegendRow = 18;
constexpr double kSwatch = 24;         // legend swatch width
constexpr double kLabelBand = 14;      // room above the frame for window/marker labels
constexpr double kColourBar = 84;      // room right of the frame for the colour bar
constexpr double kTimelineRow = 22;    // height of a timeline row
constexpr int kTimeColours = 64;       // colour steps of a path coloured by time
constexpr const char* kGridColour = "#DDDDDD";
constexpr const char* kZeroColour = "#A0A0A0";
constexpr const char* kGuideColour = "#555555";  // markers, references, start/end symbols

double text_width(std::string_view text, double font_size) {
  std::size_t code_points = 0;
  for (unsigned char c : text) code_points += (c & 0xC0) != 0x80;
  return static_cast<double>(code_points) * kEm * font_size;
}

std::string axis_title(const Axis& axis) {
  return axis.unit.empty() ? axis.label : axis.label + " (" + axis.unit + ")";
}

void require_same_length(const Series& s, const std::string& plot) {
  if (s.x.size() != s.y.size())
    throw std::invalid_argument(fmt::format("plot '{}', series '{}': {} x values for {} y values",
                                            plot, s.label, s.x.size(), s.y.size()));
}

// Finite data range of the series' x or y, widened by `extra` values.
std::pair<double, double> data_range(const std::vector<Series>& series, bool along_x,
                                     const std::vector<double>& extra = {}) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  auto take = [&](double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  };
  for (const Series& s : series)
    for (double v : along_x ? s.x : s.y) take(v);
  for (double v : extra) take(v);
  return {lo, hi};
}

// Ticks for an axis: its fixed limits, or the data range, expanded to the
// enclosing ticks plus a little room so that data never run on the frame.
Ticks axis_ticks(const Axis& axis, std::pair<double, double> range, int intervals, bool expand) {
  const bool fixed = axis.min && axis.max;
  Ticks t = nice_ticks(axis.min.value_or(range.first), axis.max.value_or(range.second), intervals,
                       expand && !fixed);
  if (fixed) {
    t.lo = *axis.min, t.hi = *axis.max;
  } else if (expand) {
    const double room = 0.03 * (t.hi - t.lo);
    if (!axis.min) t.lo -= room;
    if (!axis.max) t.hi += room;
  }
  return t;
}

// Integer ticks for a count axis over [lo, hi], with half a count of room
// each side so that markers at the ends clear the frame.
Ticks count_ticks(std::pair<double, double> range) {
  auto [lo, hi] = range;
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  Ticks t = nice_ticks(lo, hi, 10, false);
  if (t.step < 1) {
    t.step = 1;
    t.values.clear();
    for (double v = std::ceil(lo); v <= hi; ++v) t.values.push_back(v);
  }
  t.lo = lo - 0.5, t.hi = hi + 0.5;
  return t;
}

std::string dash_attribute(bool dashed) { return dashed ? " stroke-dasharray=\"7 4\"" : ""; }

std::string line_swatch(const std::string& colour, bool dashed, double width = 2) {
  return fmt::format("<line x1=\"0\" y1=\"0\" x2=\"{}\" y2=\"0\" stroke=\"{}\" stroke-width=\"{}\"{}/>",
                     kSwatch, colour, width, dash_attribute(dashed));
}

// Point marker: circle, square, triangle, diamond by shape index.
std::string point_marker(int shape, double x, double y, const std::string& colour, bool filled = true) {
  const std::string paint = fmt::format("fill=\"{}\" stroke=\"{}\" stroke-width=\"1.5\"",
                                        filled ? colour : "white", colour);
  switch (shape % 4) {
    case 0:
      return fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"4\" {}/>", x, y, paint);
    case 1:
      return fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"7\" height=\"7\" {}/>", x - 3.5,
                         y - 3.5, paint);
    case 2:
      return fmt::format("<path d=\"M{:.1f},{:.1f}l4.5,8h-9z\" {}/>", x, y - 4.5, paint);
    default:
      return fmt::format("<path d=\"M{:.1f},{:.1f}l4.5,4.5l-4.5,4.5l-4.5,-4.5z\" {}/>", x, y - 4.5,
                         paint);
  }
}

struct LegendItem {
  std::string label;
  std::string swatch;  // markup drawn in a kSwatch x 12 box centred on y = 0
};

// Viridis, stopped short of its pale yellow end so the whole path stays visible on white.
std::string viridis(double f) {
  static constexpr std::array<std::array<double, 3>, 5> stops{{
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {181, 222, 43}}};
  f = std::clamp(f, 0.0, 1.0) * (stops.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(f), stops.size() - 2);
  const double w = f - static_cast<double>(i);
  std::array<int, 3> rgb{};
  for (int c = 0; c < 3; ++c)
    rgb[c] = static_cast<int>(std::lround((1 - w) * stops[i][c] + w * stops[i + 1][c]));
  return fmt::format("#{:02X}{:02X}{:02X}", rgb[0], rgb[1], rgb[2]);
}

void append_path(fmt::memory_buffer& out, const Polyline& line) {
  char command = 'M';
  for (const auto& [x, y] : line) {
    fmt::format_to(std::back_inserter(out), "{}{:.1f},{:.1f}", command, x, y);
    command = command == 'M' ? 'L' : ' ';
  }
}

// Plot area, scales and the decorations every plot shares: title, legend,
// grid, frame, ticks, axis titles. Data go in a nested <svg> that clips them
// to the frame without needing document-wide ids.
class Canvas {
 public:
  Canvas(Size size, const std::string& title, const Axis& x_axis, const Axis& y_axis, Ticks x,
         Ticks y, const std::vector<LegendItem>& legend, bool label_band, double right_extra,
         std::vector<std::string> y_categories = {})
      : size_(size), x_(std::move(x)), y_(std::move(y)), y_categories_(std::move(y_categories)) {
    double widest = 0;
    for (double v : y_.values) widest = std::max(widest, text_width(y_label(v), kFontSize));
    left_ = std::ceil(22 + 8 + widest + 8);
    right_ = size_.width - 16 - right_extra;
    top_ = (title.empty() ? 8 : 30) + legend_rows(legend) * kLegendRow + (label_band ? kLabelBand : 0) + 6;
    bottom_ = size_.height - 46;
    if (right_ - left_ < 50 || bottom_ - top_ < 50)
      throw std::invalid_argument(fmt::format("plot '{}': {}x{} leaves no room for data", title,
                                              size_.width, size_.height));
    decorate(title, x_axis, y_axis, legend);
  }

  double px(double v) const { return left_ + (v - x_.lo) / (x_.hi - x_.lo) * (right_ - left_); }
  double py(double v) const { return bottom_ - (v - y_.lo) / (y_.hi - y_.lo) * (bottom_ - top_); }
  double left() const { return left_; }
  double right() const { return right_; }
  double top() const { return top_; }
  double bottom() const { return bottom_; }
  int columns() const { return static_cast<int>(std::lround(right_ - left_)); }
  const Ticks& x_ticks() const { return x_; }
  // Text of the y tick at v: its number, or the category at index v.
  std::string y_label(double v) const {
    return y_categories_.empty() ? tick_label(v, y_.step) : y_categories_.at(static_cast<std::size_t>(v));
  }

  // Under the data (shading), clipped.
  void add_background(const std::string& markup) { background_ += markup; }
  // The data, clipped to the frame.
  void add_data(const std::string& markup) { data_ += markup; }
  // Over everything, not clipped (labels above the frame, colour bar).
  void add_foreground(const std::string& markup) { foreground_ += markup; }

  std::string finish() const {
    return fmt::format(
        "<svg class=\"plot\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" role=\"img\" "
        "font-family=\"DejaVu Sans, Liberation Sans, Arial, sans-serif\" font-size=\"{2}\">"
        "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>{3}"
        "<svg x=\"{4}\" y=\"{5}\" width=\"{6}\" height=\"{7}\" viewBox=\"{4} {5} {6} {7}\">{8}{9}</svg>"
        "<rect x=\"{10}\" y=\"{11}\" width=\"{12}\" height=\"{13}\" fill=\"none\" stroke=\"{14}\" "
        "shape-rendering=\"crispEdges\"/>{15}</svg>",
        size_.width, size_.height, kFontSize, decorations_, left_, top_, right_ - left_,
        bottom_ - top_, background_, data_, left_ + 0.5, top_ + 0.5, right_ - left_ - 1,
        bottom_ - top_ - 1, kFrameColour, foreground_);
  }

 private:
  int legend_rows(const std::vector<LegendItem>& legend) const {
    if (legend.empty()) return 0;
    int rows = 1;
    double x = 0;
    for (const LegendItem& item : legend) {
      const double w = item_width(item);
      if (x > 0 && x + w > right_ - left_) ++rows, x = 0;
      x += w;
    }
    return rows;
  }
  static double item_width(const LegendItem& item) {
    return kSwatch + 6 + text_width(item.label, kFontSize) + 18;
  }

  void decorate(const std::string& title, const Axis& x_axis, const Axis& y_axis,
                const std::vector<LegendItem>& legend) {
    auto out = std::back_inserter(decorations_);
    if (!title.empty())
      fmt::format_to(out, "<text x=\"{}\" y=\"20\" font-size=\"{}\" font-weight=\"bold\">{}</text>",
                     left_, kTitleSize, escape(title));
    double lx = left_, ly = (title.empty() ? 8 : 30) + kLegendRow / 2;
    for (const LegendItem& item : legend) {
      const double w = item_width(item);
      if (lx > left_ && lx + w > right_) lx = left_, ly += kLegendRow;
      fmt::format_to(out, "<g transform=\"translate({:.1f},{:.1f})\">{}<text x=\"{}\" y=\"4\">{}</text></g>",
                     lx, ly, item.swatch, kSwatch + 6, escape(item.label));
      lx += w;
    }
    for (double v : x_.values) {
      const double x = std::round(px(v)) + 0.5;
      fmt::format_to(out,
                     "<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"{3}\" "
                     "shape-rendering=\"crispEdges\"/><line x1=\"{0}\" y1=\"{2}\" x2=\"{0}\" "
                     "y2=\"{4}\" stroke=\"{5}\" shape-rendering=\"crispEdges\"/>"
                     "<text x=\"{0}\" y=\"{6}\" text-anchor=\"middle\">{7}</text>",
                     x, top_, bottom_, kGridColour, bottom_ + 5, kFrameColour, bottom_ + 18,
                     tick_label(v, x_.step));
    }
    for (double v : y_.values) {
      const double y = std::round(py(v)) + 0.5;
      const bool zero = v == 0 && y_.lo < 0 && y_.hi > 0 && y_categories_.empty();
      fmt::format_to(out,
                     "<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"{3}\" "
                     "shape-rendering=\"crispEdges\"/><line x1=\"{4}\" y1=\"{1}\" x2=\"{0}\" "
                     "y2=\"{1}\" stroke=\"{5}\" shape-rendering=\"crispEdges\"/>"
                     "<text x=\"{6}\" y=\"{7}\" text-anchor=\"end\">{8}</text>",
                     left_, y, right_, zero ? kZeroColour : kGridColour, left_ - 5, kFrameColour,
                     left_ - 8, y + 4, escape(y_label(v)));
    }
    fmt::format_to(out, "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
                   (left_ + right_) / 2, bottom_ + 38, escape(axis_title(x_axis)));
    fmt::format_to(out,
                   "<text transform=\"translate(16,{}) rotate(-90)\" text-anchor=\"middle\">{}</text>",
                   (top_ + bottom_) / 2, escape(axis_title(y_axis)));
  }

  Size size_;
  Ticks x_, y_;
  std::vector<std::string> y_categories_;  // y tick labels by index (category axis); empty: numbers
  double left_ = 0, right_ = 0, top_ = 0, bottom_ = 0;
  std::string decorations_, background_, data_, foreground_;
};

// Labels above the frame at x positions, skipping any that would overlap the previous one.
std::string band_labels(std::vector<std::pair<double, std::string>> labels, const Canvas& canvas) {
  std::sort(labels.begin(), labels.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string out;
  double free_from = -std::numeric_limits<double>::infinity();
  for (const auto& [x, text] : labels) {
    const double half = text_width(text, kSmallSize) / 2;
    if (text.empty() || x - half < free_from || x < canvas.left() || x > canvas.right()) continue;
    out += fmt::format("<text x=\"{:.1f}\" y=\"{}\" font-size=\"{}\" text-anchor=\"middle\" fill=\"{}\">{}</text>",
                       x, canvas.top() - 4, kSmallSize, kGuideColour, escape(text));
    free_from = x + half + 4;
  }
  return out;
}

// Runs of finite samples in pixel coordinates, samples closer than
// `min_step` pixels to the last kept one dropped (the last of a run is kept).
std::vector<Polyline> pixel_paths(const Series& s, const Canvas& canvas, double min_step) {
  std::vector<Polyline> runs;
  Polyline run;
  auto close_run = [&](std::size_t last) {
    if (run.empty()) return;
    const std::pair<double, double> end{canvas.px(s.x[last]), canvas.py(s.y[last])};
    if (run.back() != end) run.push_back(end);
    runs.push_back(std::move(run));
    run.clear();
  };
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
      if (i > 0) close_run(i - 1);
      continue;
    }
    const std::pair<double, double> p{canvas.px(s.x[i]), canvas.py(s.y[i])};
    if (run.empty() || std::hypot(p.first - run.back().first, p.second - run.back().second) >= min_step)
      run.push_back(p);
  }
  if (!s.x.empty()) close_run(s.x.size() - 1);
  return runs;
}

std::string path_element(const std::vector<Polyline>& lines, const std::string& colour, bool dashed,
                         double width) {
  fmt::memory_buffer d;
  for (const Polyline& line : lines) append_path(d, line);
  if (d.size() == 0) return "";
  return fmt::format(
      "<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linejoin=\"round\"{}/>",
      fmt::to_string(d), colour, width, dash_attribute(dashed));
}

// Path 0 of a trajectory split into kTimeColours pieces by the time of its samples.
std::string time_coloured_path(const Series& s, const std::vector<double>& time, const Ticks& t,
                               const Canvas& canvas) {
  std::vector<std::vector<Polyline>> pieces(kTimeColours);
  int current = -1;
  Polyline piece;
  auto flush = [&] {
    if (piece.size() > 1) pieces[current].push_back(piece);
    piece.clear();
  };
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || !std::isfinite(time[i])) {
      flush();
      current = -1;
      continue;
    }
    const int colour = std::clamp(static_cast<int>((time[i] - t.lo) / (t.hi - t.lo) * kTimeColours),
                                  0, kTimeColours - 1);
    const std::pair<double, double> p{canvas.px(s.x[i]), canvas.py(s.y[i])};
    if (colour != current && current >= 0) {
      piece.push_back(p);  // pieces share their boundary sample: no gaps
      flush();
    }
    current = colour;
    if (piece.empty() || std::hypot(p.first - piece.back().first, p.second - piece.back().second) >= 0.5 ||
        i + 1 == s.x.size())
      piece.push_back(p);
  }
  flush();
  std::string out;
  for (int c = 0; c < kTimeColours; ++c)
    out += path_element(pieces[c], viridis((c + 0.5) / kTimeColours), false, 2);
  return out;
}

std::string colour_bar(const Ticks& t, const Axis& axis, const Canvas& canvas) {
  const double x = canvas.right() + 20, h = canvas.bottom() - canvas.top();
  std::string out;
  for (int c = 0; c < kTimeColours; ++c) {
    const double y0 = canvas.bottom() - h * (c + 1) / kTimeColours;
    out += fmt::format("<rect x=\"{}\" y=\"{:.2f}\" width=\"12\" height=\"{:.2f}\" fill=\"{}\"/>", x, y0,
                       h / kTimeColours + 0.3, viridis((c + 0.5) / kTimeColours));
  }
  out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"{}\" fill=\"none\" stroke=\"{}\"/>", x,
                     canvas.top(), h, kGuideColour);
  for (double v : t.values) {
    const double y = canvas.bottom() - (v - t.lo) / (t.hi - t.lo) * h;
    out += fmt::format("<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"{3}\"/>"
                       "<text x=\"{4}\" y=\"{5:.1f}\">{6}</text>",
                       x + 12, y, x + 16, kGuideColour, x + 19, y + 4, tick_label(v, t.step));
  }
  out += fmt::format("<text transform=\"translate({},{}) rotate(-90)\" text-anchor=\"middle\">{}</text>",
                     canvas.right() + kColourBar - 6, (canvas.top() + canvas.bottom()) / 2,
                     escape(axis_title(axis)));
  return out;
}

}  // namespace

const std::vector<std::string>& palette() {
  static const std::vector<std::string> colours{"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                "#E69F00", "#56B4E9", "#000000"};
  return colours;
}

std::string escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

Ticks nice_ticks(double lo, double hi, int intervals, bool expand) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0, hi = 1;
  if (hi < lo) std::swap(lo, hi);
  const double scale = std::max(std::abs(lo), std::abs(hi));
  if (hi - lo <= 1e-12 * scale || hi == lo) {
    const double half = scale > 0 ? 0.1 * scale : 1;
    lo -= half, hi += half;
  }
  const double raw = (hi - lo) / std::max(intervals, 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double fraction = raw / magnitude;
  const double step = (fraction < 1.5 ? 1 : fraction < 3 ? 2 : fraction < 7 ? 5 : 10) * magnitude;
  constexpr double kSlack = 1e-9;  // a bound within rounding of a tick is on it
  const long first = static_cast<long>(expand ? std::floor(lo / step + kSlack) : std::ceil(lo / step - kSlack));
  const long last = static_cast<long>(expand ? std::ceil(hi / step - kSlack) : std::floor(hi / step + kSlack));
  Ticks t{expand ? first * step : lo, expand ? last * step : hi, step, {}};
  for (long k = first; k <= last; ++k) t.values.push_back(k == 0 ? 0.0 : k * step);
  return t;
}

std::string tick_label(double value, double step) {
  if (std::abs(value) < 1e-6 * step) value = 0;
  std::string text;
  if (std::max(std::abs(value), step) >= 1e6 || step < 1e-5)
    text = fmt::format("{:g}", value);
  else
    text = fmt::format("{:.{}f}", value, std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9))));
  if (!text.empty() && text[0] == '-') text = "\u2212" + text.substr(1);
  return text;
}

std::vector<Polyline> display_polylines(const std::vector<double>& x, const std::vector<double>& y,
                                        double x_lo, double x_hi, int columns) {
  std::vector<Polyline> runs;
  Polyline run;
  const std::size_t n = std::min(x.size(), y.size());
  std::size_t bucket_start = 0;
  long bucket_column = 0;
  const double per_unit = x_hi > x_lo ? std::max(columns, 1) / (x_hi - x_lo) : 0;  // no range: one column
  auto column_of = [&](double v) {
    // Samples left or right of the range share one bucket each side.
    return static_cast<long>(std::clamp(std::floor((v - x_lo) * per_unit), -1.0,
                                        static_cast<double>(std::max(columns, 1))));
  };
  auto flush_bucket = [&](std::size_t end) {  // samples [bucket_start, end)
    if (end <= bucket_start) return;
    std::size_t low = bucket_start, high = bucket_start;
    for (std::size_t i = bucket_start; i < end; ++i) {
      if (y[i] < y[low]) low = i;
      if (y[i] > y[high]) high = i;
    }
    std::array<std::size_t, 4> keep{bucket_start, low, high, end - 1};
    std::sort(keep.begin(), keep.end());
    for (std::size_t k = 0; k < keep.size(); ++k)
      if (k == 0 || keep[k] != keep[k - 1]) run.emplace_back(x[keep[k]], y[keep[k]]);
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) {
      flush_bucket(i);
      if (!run.empty()) runs.push_back(std::move(run));
      run.clear();
      bucket_start = i + 1;
      continue;
    }
    const long column = column_of(x[i]);
    if (i > bucket_start && column != bucket_column) {
      flush_bucket(i);
      bucket_start = i;
    }
    bucket_column = column;
  }
  flush_bucket(n);
  if (!run.empty()) runs.push_back(std::move(run));
  return runs;
}

std::string render(const LinePlot& plot) {
  std::vector<double> guides;
  for (const Window& w : plot.windows) guides.insert(guides.end(), {w.start, w.end});
  for (const Marker& m : plot.markers) guides.push_back(m.x);
  for (const Series& s : plot.series) require_same_length(s, plot.title);

  std::vector<LegendItem> legend;
  for (std::size_t i = 0; i < plot.series.size(); ++i)
    if (!plot.series[i].label.empty())
      legend.push_back({plot.series[i].label,
                        line_swatch(palette()[i % palette().size()], plot.series[i].dashed)});
  if (!plot.windows.empty() && !plot.windows_legend.empty())
    legend.push_back({plot.windows_legend,
                      fmt::format("<rect x=\"0\" y=\"-6\" width=\"{}\" height=\"12\" fill=\"{}\" "
                                  "fill-opacity=\"0.45\"/>", kSwatch, kWindowColour)});
  if (!plot.markers.empty() && !plot.markers_legend.empty())
    legend.push_back({plot.markers_legend,
                      fmt::format("<line x1=\"{0}\" y1=\"-7\" x2=\"{0}\" y2=\"7\" stroke=\"{1}\" "
                                  "stroke-dasharray=\"3 2\"/>", kSwatch / 2, kGuideColour)});
  bool labelled = false;
  for (const Window& w : plot.windows) labelled |= !w.label.empty();
  for (const Marker& m : plot.markers) labelled |= !m.label.empty();

  Canvas canvas(plot.size, plot.title, plot.x, plot.y,
                axis_ticks(plot.x, data_range(plot.series, true, guides), 10, false),
                axis_ticks(plot.y, data_range(plot.series, false), 6, true), legend, labelled, 0);

  std::vector<std::pair<double, std::string>> labels;
  for (const Window& w : plot.windows) {
    canvas.add_background(fmt::format(
        "<rect x=\"{:.1f}\" y=\"{}\" width=\"{:.1f}\" height=\"{}\" fill=\"{}\" fill-opacity=\"0.45\"/>",
        canvas.px(w.start), canvas.top(), canvas.px(w.end) - canvas.px(w.start),
        canvas.bottom() - canvas.top(), kWindowColour));
    labels.emplace_back((canvas.px(w.start) + canvas.px(w.end)) / 2, w.label);
  }
  for (const Marker& m : plot.markers) {
    canvas.add_background(fmt::format(
        "<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"{3}\" stroke-dasharray=\"3 2\"/>",
        canvas.px(m.x), canvas.top(), canvas.bottom(), kGuideColour));
    labels.emplace_back(canvas.px(m.x), m.label);
  }
  canvas.add_foreground(band_labels(std::move(labels), canvas));

  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    std::vector<Polyline> lines =
        display_polylines(s.x, s.y, canvas.x_ticks().lo, canvas.x_ticks().hi, canvas.columns());
    for (Polyline& line : lines)
      for (auto& [x, y] : line) x = canvas.px(x), y = canvas.py(y);
    canvas.add_data(path_element(lines, palette()[i % palette().size()], s.dashed, 1.5));
  }
  return canvas.finish();
}

std::string render(const TrajectoryPlot& plot) {
  for (const Series& s : plot.paths) require_same_length(s, plot.title);
  const bool by_time = !plot.time.empty();
  if (by_time && (plot.paths.empty() || plot.time.size() != plot.paths[0].x.size()))
    throw std::invalid_argument(fmt::format("plot '{}': {} time values for {} samples of the first path",
                                            plot.title, plot.time.size(),
                                            plot.paths.empty() ? 0 : plot.paths[0].x.size()));
  std::vector<LegendItem> legend;
  for (std::size_t i = 0; i < plot.paths.size(); ++i) {
    if (plot.paths[i].label.empty()) continue;
    legend.push_back({plot.paths[i].label,
                      by_time && i == 0
                          ? fmt::format("<path d=\"M0,0h8\" stroke=\"{}\" stroke-width=\"2\"/><path d=\"M8,0h8\" "
                                        "stroke=\"{}\" stroke-width=\"2\"/><path d=\"M16,0h8\" stroke=\"{}\" "
                                        "stroke-width=\"2\"/>", viridis(0), viridis(0.5), viridis(1))
                          : line_swatch(palette()[i % palette().size()], plot.paths[i].dashed)});
  }
  legend.push_back({"start", point_marker(0, kSwatch / 2, 0, kGuideColour, false)});
  legend.push_back({"end", point_marker(1, kSwatch / 2, 0, kGuideColour)});

  const Ticks time_ticks = by_time ? axis_ticks(plot.time_axis, data_range({{"", plot.time, plot.time}}, true), 5, false)
                                   : Ticks{};
  Canvas canvas(plot.size, plot.title, plot.x, plot.y, axis_ticks(plot.x, data_range(plot.paths, true), 6, true),
                axis_ticks(plot.y, data_range(plot.paths, false), 6, true), legend, false,
                by_time ? kColourBar : 0);
  std::string ends;
  for (std::size_t i = 0; i < plot.paths.size(); ++i) {
    const Series& s = plot.paths[i];
    const std::vector<Polyline> lines = pixel_paths(s, canvas, 0.5);
    canvas.add_data(by_time && i == 0
                        ? time_coloured_path(s, plot.time, time_ticks, canvas)
                        : path_element(lines, palette()[i % palette().size()], s.dashed, 1.5));
    if (lines.empty()) continue;
    const auto& [x0, y0] = lines.front().front();
    const auto& [x1, y1] = lines.back().back();
    ends += point_marker(0, x0, y0, kGuideColour, false) + point_marker(1, x1, y1, kGuideColour);
  }
  canvas.add_data(ends);
  if (by_time) canvas.add_foreground(colour_bar(time_ticks, plot.time_axis, canvas));
  return canvas.finish();
}

std::string render(const PointPlot& plot) {
  for (const Series& s : plot.series) require_same_length(s, plot.title);
  std::vector<LegendItem> legend;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    if (plot.series[i].label.empty()) continue;
    const std::string& colour = palette()[i % palette().size()];
    legend.push_back({plot.series[i].label,
                      (plot.join ? line_swatch(colour, plot.series[i].dashed, 1) : "") +
                          point_marker(static_cast<int>(i), kSwatch / 2, 0, colour)});
  }
  std::vector<double> reference_values;
  for (std::size_t r = 0; r < plot.references.size(); ++r) {
    reference_values.push_back(plot.references[r].y);
    legend.push_back({plot.references[r].label,
                      fmt::format("<line x1=\"0\" y1=\"0\" x2=\"{}\" y2=\"0\" stroke=\"{}\" "
                                  "stroke-width=\"1.5\" stroke-dasharray=\"{}\"/>",
                                  kSwatch, kGuideColour, r % 2 ? "2 2" : "6 3")});
  }
  const Ticks x = plot.integer_x && !(plot.x.min && plot.x.max)
                      ? count_ticks(data_range(plot.series, true))
                      : axis_ticks(plot.x, data_range(plot.series, true), 10, true);
  Canvas canvas(plot.size, plot.title, plot.x, plot.y, x,
                axis_ticks(plot.y, data_range(plot.series, false, reference_values), 6, true), legend,
                false, 0);
  for (std::size_t r = 0; r < plot.references.size(); ++r)
    canvas.add_background(fmt::format(
        "<line x1=\"{0}\" y1=\"{2:.1f}\" x2=\"{1}\" y2=\"{2:.1f}\" stroke=\"{3}\" stroke-width=\"1.5\" "
        "stroke-dasharray=\"{4}\"/>",
        canvas.left(), canvas.right(), canvas.py(plot.references[r].y), kGuideColour, r % 2 ? "2 2" : "6 3"));
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    const std::string& colour = palette()[i % palette().size()];
    const std::vector<Polyline> lines = pixel_paths(s, canvas, 0);
    if (plot.join) canvas.add_data(path_element(lines, colour, s.dashed, 1));
    std::string markers;
    for (const Polyline& line : lines)
      for (const auto& [px, py] : line) markers += point_marker(static_cast<int>(i), px, py, colour);
    canvas.add_data(markers);
  }
  return canvas.finish();
}

std::string render(const TimelinePlot& plot) {
  const int rows = static_cast<int>(plot.rows.size());
  std::vector<double> ends;
  std::vector<std::string> labels(plot.rows.size());
  for (int r = 0; r < rows; ++r) {
    labels[rows - 1 - r] = plot.rows[r].label;  // first row on top: the highest tick
    for (const auto& [start, end] : plot.rows[r].spans) ends.insert(ends.end(), {start, end});
  }
  Ticks y{-0.5, rows - 0.5, 1, {}};
  for (int r = 0; r < rows; ++r) y.values.push_back(r);
  const Size size{plot.width, static_cast<int>(std::ceil((plot.title.empty() ? 8 : 30) + 6 + 46 +
                                                         std::max(rows, 3) * kTimelineRow))};
  Canvas canvas(size, plot.title, plot.x, {}, axis_ticks(plot.x, data_range({}, true, ends), 10, false), y, {},
                false, 0, labels);
  const double bar = 0.7 * kTimelineRow;
  for (int r = 0; r < rows; ++r) {
    const TimelineRow& row = plot.rows[r];
    const std::string& colour = row.colour.empty() ? palette()[r % palette().size()] : row.colour;
    fmt::memory_buffer bars;
    for (const auto& [start, end] : row.spans)  // at least a pixel wide, so short spans show
      fmt::format_to(std::back_inserter(bars), "<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\"/>",
                     canvas.px(start), canvas.py(rows - 1 - r) - bar / 2,
                     std::max(1.0, canvas.px(end) - canvas.px(start)), bar);
    canvas.add_data(fmt::format("<g fill=\"{}\">{}</g>", colour, fmt::to_string(bars)));
  }
  return canvas.finish();
}

}  // namespace freestand::svg
