#ifndef FREESTAND_POST_SVG_PLOT_H
#define FREESTAND_POST_SVG_PLOT_H

// Engineering plots as inline SVG for the HTML report (docs/report.md):
// time histories sharing axes, trajectories (modal-interaction diagrams) and
// point plots (impact decay). Output is plain SVG markup, no script, no
// external reference; long series are reduced to what a pixel column can show.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace freestand::svg {

// Series colours in the order series take them: Okabe & Ito's colour-blind-safe
// palette without its yellow, which is used to shade windows.
const std::vector<std::string>& palette();
inline constexpr const char* kWindowColour = "#F0E442";
inline constexpr const char* kFrameColour = "#333333";  // plot frame and its ticks only

struct Axis {
  std::string label;               // quantity, e.g. "rock_x"
  std::string unit;                // e.g. "rad"; empty: dimensionless
  std::optional<double> min, max;  // fixed limits; unset: from the data
};

struct Series {
  std::string label;          // legend entry; empty: not in the legend
  std::vector<double> x, y;   // same length; a NaN in x or y breaks the line
  bool dashed = false;
};

struct Window {  // shaded x interval, e.g. where simulation and recording disagree
  double start = 0, end = 0;
  std::string label;  // written above the frame; may be empty
};

struct Marker {  // vertical line at an event, e.g. an impact
  double x = 0;
  std::string label;  // written above the frame; may be empty
};

struct Size {
  int width = 880, height = 340;  // SVG user units (CSS pixels at 100 %)
};

// Series against a shared, ascending x (time histories).
struct LinePlot {
  std::string title;
  Axis x, y;
  std::vector<Series> series;
  std::vector<Window> windows;
  std::string windows_legend;  // legend entry for the shading; empty: none
  std::vector<Marker> markers;
  std::string markers_legend;  // legend entry for the marker lines; empty: none
  Size size;
};

// y against x in sample order, e.g. rock_x against slide_x. With `time` (one
// value per sample of paths[0]) the first path is coloured by time and a
// colour bar added; every path gets a start (circle) and end (square) marker.
struct TrajectoryPlot {
  std::string title;
  Axis x, y;
  std::vector<Series> paths;
  std::vector<double> time;
  Axis time_axis{"t", "s", {}, {}};
  Size size{620, 460};
};

struct Reference {  // horizontal line, e.g. Housner's coefficient of restitution
  double y = 0;
  std::string label;
};

// Markers against x, e.g. the ratio of angular velocities across impact n.
struct PointPlot {
  std::string title;
  Axis x, y;
  std::vector<Series> series;
  std::vector<Reference> references;
  bool join = true;       // thin line between a series' points
  bool integer_x = true;  // x counts something: integer ticks only
  Size size{620, 340};
};

// Categories against x, one row each with bars where the category holds, e.g.
// a body's modes of motion over time (a Gantt chart).
struct TimelineRow {
  std::string label;
  std::vector<std::pair<double, double>> spans;  // [start, end] intervals of x
  std::string colour;                            // bar colour; empty: palette()[row]
};
struct TimelinePlot {
  std::string title;
  Axis x;
  std::vector<TimelineRow> rows;  // top to bottom
  int width = 880;                // the height follows from the number of rows
};

std::string render(const LinePlot& plot);
std::string render(const TimelinePlot& plot);
std::string render(const TrajectoryPlot& plot);
std::string render(const PointPlot& plot);

// ---- building blocks, exposed for tests ----

struct Ticks {
  double lo = 0, hi = 1, step = 1;  // axis range and tick spacing
  std::vector<double> values;       // k * step inside [lo, hi]
};
// Ticks at 1, 2 or 5 x 10^k with about `intervals` intervals over [lo, hi].
// expand: the range grows to the enclosing ticks; otherwise it stays [lo, hi].
// A degenerate or non-finite range is widened so that it always has ticks.
Ticks nice_ticks(double lo, double hi, int intervals, bool expand);
// Tick text with as many decimals as the step needs and a true minus sign.
std::string tick_label(double value, double step);

using Polyline = std::vector<std::pair<double, double>>;
// The runs of finite (x, y) samples of an ascending x (a NaN ends a run), each
// reduced to at most four samples per column of [x_lo, x_hi] split into
// `columns`: the first, lowest, highest and last of the column, in sample
// order, so peaks and the line's continuity survive.
std::vector<Polyline> display_polylines(const std::vector<double>& x, const std::vector<double>& y,
                                        double x_lo, double x_hi, int columns);

// Text made safe for XML and HTML content and attribute values.
std::string escape(std::string_view text);

}  // namespace freestand::svg

#endif
