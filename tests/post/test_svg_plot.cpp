// svg_plot: tick generation, display reduction of long series, NaN gaps,
// escaping and the markup of the three plot kinds.

#include "svg_plot.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <regex>

namespace freestand::svg {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Mantissa of a tick step: must be 1, 2 or 5.
double mantissa(double step) { return step / std::pow(10.0, std::floor(std::log10(step) + 1e-9)); }

TEST(NiceTicks, TimeAxisOfAFiftySixSecondRecord) {
  const Ticks tight = nice_ticks(0, 56, 10, false);
  EXPECT_DOUBLE_EQ(tight.step, 5);
  EXPECT_DOUBLE_EQ(tight.lo, 0);
  EXPECT_DOUBLE_EQ(tight.hi, 56);
  ASSERT_EQ(tight.values.size(), 12u);  // 0, 5, ..., 55
  EXPECT_DOUBLE_EQ(tight.values.back(), 55);

  const Ticks expanded = nice_ticks(-0.0123, 0.0311, 6, true);
  EXPECT_DOUBLE_EQ(expanded.step, 0.01);
  EXPECT_NEAR(expanded.lo, -0.02, 1e-15);
  EXPECT_NEAR(expanded.hi, 0.04, 1e-15);
  EXPECT_EQ(expanded.values.size(), 7u);
}

// Random ranges over many decades: the step is 1, 2 or 5 x 10^k, ticks are
// multiples of it inside the axis range, an expanded axis covers the data, and
// the count stays near what was asked (the 1-2-5 ladder allows a factor ~2.5).
TEST(NiceTicks, PropertiesOverRandomRanges) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> exponent(-6, 6), unit(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, exponent(rng));
    double lo = unit(rng) * scale, hi = unit(rng) * scale;
    if (lo > hi) std::swap(lo, hi);
    for (bool expand : {false, true}) {
      const Ticks t = nice_ticks(lo, hi, 6, expand);
      SCOPED_TRACE(testing::Message() << "lo=" << lo << " hi=" << hi << " expand=" << expand);
      const double m = mantissa(t.step);
      EXPECT_TRUE(std::abs(m - 1) < 1e-9 || std::abs(m - 2) < 1e-9 || std::abs(m - 5) < 1e-9) << m;
      ASSERT_GE(t.values.size(), 2u);
      EXPECT_LE(t.values.size(), 16u);
      for (double v : t.values) {
        EXPECT_NEAR(v / t.step, std::round(v / t.step), 1e-6);
        EXPECT_GE(v, t.lo - 1e-9 * t.step);
        EXPECT_LE(v, t.hi + 1e-9 * t.step);
      }
      if (expand) EXPECT_TRUE(t.lo <= lo && t.hi >= hi);
    }
  }
}

TEST(NiceTicks, DegenerateAndNonFiniteRangesStillHaveTicks) {
  const Ticks constant = nice_ticks(3, 3, 6, true);
  EXPECT_LT(constant.lo, 3);
  EXPECT_GT(constant.hi, 3);
  EXPECT_GE(constant.values.size(), 2u);
  const Ticks zero = nice_ticks(0, 0, 6, true);
  EXPECT_GE(zero.values.size(), 2u);
  const Ticks none = nice_ticks(kNaN, kNaN, 6, true);
  EXPECT_DOUBLE_EQ(none.lo, 0);
  EXPECT_DOUBLE_EQ(none.hi, 1);
}

TEST(TickLabel, DecimalsFollowTheStepAndMinusIsTypographic) {
  EXPECT_EQ(tick_label(0.1 + 0.2, 0.1), "0.3");
  EXPECT_EQ(tick_label(-0.02, 0.01), "\u22120.02");
  EXPECT_EQ(tick_label(50, 10), "50");
  EXPECT_EQ(tick_label(2.5, 0.5), "2.5");
  EXPECT_EQ(tick_label(-1e-18, 0.05), "0.00");  // rounding noise is not "-0.00"
}

TEST(DisplayPolylines, KeepsExtremesOfALongRecord) {
  // 56 s at 1 kHz of small noise with one spike up and one down.
  const std::size_t n = 56001;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.01);
  std::vector<double> t(n), y(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = i * 1e-3, y[i] = noise(rng);
  y[31415] = 10;
  y[27182] = -7;
  const int columns = 800;
  const auto lines = display_polylines(t, y, 0, 56, columns);
  ASSERT_EQ(lines.size(), 1u);
  const Polyline& line = lines[0];
  EXPECT_LE(line.size(), 4u * (columns + 1));  // the last sample, t = 56, opens column 800
  EXPECT_GT(line.size(), 2u * columns);        // noise: first, min, max, last mostly differ
  EXPECT_EQ(line.front(), std::make_pair(t[0], y[0]));
  EXPECT_EQ(line.back(), std::make_pair(t[n - 1], y[n - 1]));
  EXPECT_NE(std::find(line.begin(), line.end(), std::make_pair(t[31415], 10.0)), line.end());
  EXPECT_NE(std::find(line.begin(), line.end(), std::make_pair(t[27182], -7.0)), line.end());
  EXPECT_TRUE(std::is_sorted(line.begin(), line.end()));  // sample order kept
  // Every column's extremes survive: the reduced line has the same max and min per column.
  for (int c = 0; c < columns; c += 97) {
    double data_max = -1e9, shown_max = -1e9;
    for (std::size_t i = 0; i < n; ++i)
      if (static_cast<int>(std::floor(t[i] / 56 * columns)) == c) data_max = std::max(data_max, y[i]);
    for (const auto& [x, v] : line)
      if (static_cast<int>(std::floor(x / 56 * columns)) == c) shown_max = std::max(shown_max, v);
    EXPECT_EQ(shown_max, data_max) << "column " << c;
  }
}

TEST(DisplayPolylines, ShortSeriesPassUnchanged) {
  const std::vector<double> t{0, 1, 2, 3}, y{0, 2, -1, 5};
  const auto lines = display_polylines(t, y, 0, 3, 800);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].size(), 4u);
}

TEST(DisplayPolylines, EmptyRangeIsOneColumn) {
  const std::vector<double> t{1, 1, 1, 1, 1}, y{0, 3, -2, 1, 0.5};
  const auto lines = display_polylines(t, y, 1, 1, 800);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], (Polyline{{1, 0}, {1, 3}, {1, -2}, {1, 0.5}}));  // first, max, min, last
}

TEST(DisplayPolylines, NaNInXOrYBreaksTheLine) {
  const std::vector<double> t{0, 1, 2, 3, kNaN, 5, 6, 7}, y{0, 1, kNaN, 3, 4, 5, 6, 7};
  const auto lines = display_polylines(t, y, 0, 7, 800);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].size(), 2u);  // t = 0, 1
  EXPECT_EQ(lines[1].size(), 1u);  // t = 3 alone
  EXPECT_EQ(lines[2].size(), 3u);  // t = 5, 6, 7
}

TEST(Escape, MarkupCharacters) {
  EXPECT_EQ(escape("<a & 'b' \"c\">"), "&lt;a &amp; &#39;b&#39; &quot;c&quot;&gt;");
  EXPECT_EQ(escape("rock_x (rad)"), "rock_x (rad)");
}

LinePlot two_series_plot() {
  LinePlot plot;
  plot.title = "Rocking <rock_x> & more";
  plot.x = {"t", "s", {}, {}};
  plot.y = {"rock_x", "rad", {}, {}};
  Series recorded{"recorded", {}, {}}, simulated{"simulated", {}, {}};
  for (int i = 0; i <= 2000; ++i) {
    const double t = i * 0.01;
    recorded.x.push_back(t);
    simulated.x.push_back(t);
    recorded.y.push_back(t > 8 && t < 9 ? kNaN : 0.05 * std::sin(t));
    simulated.y.push_back(0.05 * std::sin(t + 0.1));
  }
  plot.series = {recorded, simulated};
  plot.windows = {{12, 14, "mismatch"}};
  plot.markers = {{3.14, "n=1"}, {6.28, "n=2"}};
  return plot;
}

// The path drawn in `colour`.
std::string path_of(const std::string& svg, const std::string& colour) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(svg, m, std::regex("<path d=\"([^\"]*)\" fill=\"none\" stroke=\"" + colour)))
      << colour;
  return m.size() > 1 ? m[1].str() : "";
}

TEST(LinePlot, NaNGapIsAMoveInThePathAndTextIsEscaped) {
  const std::string svg = render(two_series_plot());
  const std::string recorded = path_of(svg, palette()[0]), simulated = path_of(svg, palette()[1]);
  EXPECT_EQ(std::count(recorded.begin(), recorded.end(), 'M'), 2);
  EXPECT_EQ(std::count(simulated.begin(), simulated.end(), 'M'), 1);
  EXPECT_NE(svg.find("Rocking &lt;rock_x&gt; &amp; more"), std::string::npos);
  EXPECT_EQ(svg.find("<rock_x>"), std::string::npos);
  EXPECT_NE(svg.find("rock_x (rad)"), std::string::npos);
  EXPECT_NE(svg.find(">mismatch<"), std::string::npos);
  EXPECT_NE(svg.find(">n=2<"), std::string::npos);
  EXPECT_EQ(svg.find("<script"), std::string::npos);
  EXPECT_EQ(svg.find("http"), std::string::npos);  // no namespace URL either: inline SVG needs none
}

TEST(LinePlot, FiftySixSecondRecordAtOneKilohertzStaysLight) {
  LinePlot plot;
  plot.x = {"t", "s", {}, {}};
  plot.y = {"rock_x", "rad", {}, {}};
  for (int s = 0; s < 2; ++s) {
    Series series{s ? "simulated" : "recorded", {}, {}};
    for (int i = 0; i <= 56000; ++i)
      series.x.push_back(i * 1e-3), series.y.push_back(std::exp(-0.05 * i * 1e-3) * std::sin(7.0 * i * 1e-3 + s));
    plot.series.push_back(series);
  }
  const std::string svg = render(plot);
  // Raw, the two series would be 112 002 points (~1.5 MB of coordinates).
  EXPECT_LT(svg.size(), 120000u) << svg.size();
}

TEST(LinePlot, MismatchedLengthsNameTheSeries) {
  LinePlot plot = two_series_plot();
  plot.series[1].y.pop_back();
  try {
    render(plot);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("simulated"), std::string::npos) << e.what();
  }
}

TEST(TrajectoryPlot, ColouredByTimeHasColourBarAndEndMarkers) {
  TrajectoryPlot plot;
  plot.x = {"slide_x", "mm", {}, {}};
  plot.y = {"rock_x", "rad", {}, {}};
  Series path{"simulated", {}, {}};
  for (int i = 0; i <= 1000; ++i) {
    plot.time.push_back(i * 0.01);
    path.x.push_back(i * 0.1);
    path.y.push_back(0.02 * std::sin(i * 0.05));
  }
  plot.paths = {path};
  const std::string svg = render(plot);
  EXPECT_NE(svg.find("t (s)"), std::string::npos);  // colour-bar title
  EXPECT_NE(svg.find("<circle"), std::string::npos);
  EXPECT_NE(svg.find(">start<"), std::string::npos);
  EXPECT_NE(svg.find(">end<"), std::string::npos);
  plot.time.pop_back();
  EXPECT_THROW(render(plot), std::invalid_argument);
}

TEST(PointPlot, IntegerTicksForImpactNumbers) {
  PointPlot plot;
  plot.x = {"impact n", "", {}, {}};
  plot.y = {"ω after / ω before", "", {}, {}};
  plot.series = {{"simulated", {1, 2, 3}, {0.9, 0.88, 0.86}}};
  plot.references = {{0.85, "Housner"}};
  const std::string svg = render(plot);
  EXPECT_NE(svg.find(">1<"), std::string::npos);
  EXPECT_NE(svg.find(">3<"), std::string::npos);
  EXPECT_EQ(svg.find(">1.5<"), std::string::npos);
  EXPECT_EQ(svg.find(">2.5<"), std::string::npos);
  EXPECT_NE(svg.find(">Housner<"), std::string::npos);
}

TEST(TimelinePlot, RowsAreLabelledCategoriesWithBarsWhereTheyHold) {
  TimelinePlot plot;
  plot.title = "Modes";
  plot.x = {"t", "s", 0.0, 10.0};
  plot.rows = {{"rest", {{0, 4}, {6, 10}}, "#A0A0A0"}, {"rock & slide", {{4, 6}, {5, 5.0001}}, ""}};
  const std::string svg = render(plot);
  EXPECT_NE(svg.find(">rest<"), std::string::npos);
  EXPECT_NE(svg.find(">rock &amp; slide<"), std::string::npos);  // category labels replace numbers, escaped
  const std::regex bar(R"re(<rect x="[0-9.]+" y="[0-9.]+" width="([0-9.]+)" height="[0-9.]+"/>)re");
  std::vector<double> widths;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), bar); it != std::sregex_iterator(); ++it)
    widths.push_back(std::stod((*it)[1]));
  ASSERT_EQ(widths.size(), 4u);
  EXPECT_NEAR(widths[0] / widths[2], 2.0, 0.01);  // 4 s against 2 s
  EXPECT_EQ(widths[3], 1.0);                       // a 0.1 ms span still shows, a pixel wide
  EXPECT_NE(svg.find("fill=\"#A0A0A0\""), std::string::npos);
  EXPECT_NE(svg.find("fill=\"" + palette()[1] + "\""), std::string::npos);  // no colour: the row's palette colour
}

}  // namespace
}  // namespace freestand::svg
