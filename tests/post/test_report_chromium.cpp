// The report as a browser shows it: a report of synthetic data (decaying
// rocking, a sliding ramp, a modal-interaction diagram, impact decay, an error
// table) is rendered by headless Chromium and the screenshot is checked: each
// plot frame is found and holds its series' colours where the data are, and
// nothing where the recording has a gap.
//
// FREESTAND_REPORT_EXAMPLE_DIR=DIR keeps report.html and screenshot.png in DIR
// (docs/report.md shows them).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "chromium_screenshot.h"
#include "html_report.h"
#include "svg_plot.h"

namespace freestand {
namespace {

namespace fs = std::filesystem;
using namespace freestand::test;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Synthetic signals. Rocking: a decaying oscillation, 20 s at 1 kHz; the
// "recording" lags a little (its lines stay a few pixels apart from the
// simulated ones) and has a dropout (NaN) from kGapStart to kGapEnd.
constexpr double kDuration = 20, kGapStart = 8, kGapEnd = 9.5;
constexpr double kRecordedLag = 0.15, kRecordedSlideStart = 4.5;

double rocking(double t, double lag) { return 0.04 * std::exp(-0.15 * t) * std::sin(2 * M_PI * 0.9 * (t - lag)); }
double sliding(double t, double delay) { return t < delay ? 0 : 12 * (t - delay); }  // mm

HtmlReport synthetic_report() {
  svg::Series rock_recorded{"recorded", {}, {}}, rock_simulated{"simulated", {}, {}};
  svg::Series slide_recorded{"recorded", {}, {}}, slide_simulated{"simulated", {}, {}};
  std::vector<double> time;
  for (int i = 0; i <= kDuration * 1000; ++i) {
    const double t = i * 1e-3;
    time.push_back(t);
    const bool gap = t > kGapStart && t < kGapEnd;
    rock_recorded.x.push_back(t), rock_recorded.y.push_back(gap ? kNaN : rocking(t, kRecordedLag));
    rock_simulated.x.push_back(t), rock_simulated.y.push_back(rocking(t, 0));
    slide_recorded.x.push_back(t), slide_recorded.y.push_back(sliding(t, kRecordedSlideStart));
    slide_simulated.x.push_back(t), slide_simulated.y.push_back(sliding(t, 4.0));
  }
  HtmlReport report("Synthetic block on a shake table");
  report.add_metadata("recording", "synthetic (test data)");
  report.add_metadata("simulation", "synthetic (test data)");
  report.add_section("Rocking and sliding");
  report.add_paragraph("Simulated and recorded time histories, on the same axes.");

  svg::LinePlot rock;
  rock.title = "Rocking angle";
  rock.x = {"t", "s", {}, {}};
  rock.y = {"rock_x", "rad", {}, {}};
  rock.series = {rock_recorded, rock_simulated};
  rock.windows = {{14, 16, "mismatch"}};
  rock.windows_legend = "mismatch window";
  for (int n = 1; n <= 12; ++n) rock.markers.push_back({(n - 0.5) / 1.8, "n=" + std::to_string(n)});
  rock.markers_legend = "impact";
  report.add_figure(svg::render(rock), "Rocking angle about x, recorded and simulated.");

  svg::LinePlot slide;
  slide.title = "Sliding displacement";
  slide.x = {"t", "s", {}, {}};
  slide.y = {"slide_x", "mm", {}, {}};
  slide.series = {slide_recorded, slide_simulated};
  report.add_figure(svg::render(slide), "Sliding along x relative to the table.");

  report.add_section("Modal interaction and impacts");
  svg::TrajectoryPlot modal;
  modal.title = "Rocking against sliding";
  modal.x = {"slide_x", "mm", {}, {}};
  modal.y = {"rock_x", "rad", {}, {}};
  modal.paths = {{"simulated", slide_simulated.y, rock_simulated.y}};
  modal.time = time;
  report.add_figure(svg::render(modal), "Modal-interaction diagram, coloured by time.");

  svg::PointPlot decay;
  decay.title = "Impact decay";
  decay.x = {"impact n", "", {}, {}};
  decay.y = {"ω after / ω before", "", {}, {}};
  svg::Series decay_recorded{"recorded", {}, {}}, decay_simulated{"simulated", {}, {}};
  for (int n = 1; n <= 12; ++n) {
    decay_recorded.x.push_back(n), decay_recorded.y.push_back(0.80 + 0.03 * std::sin(n));
    decay_simulated.x.push_back(n), decay_simulated.y.push_back(0.84 - 0.002 * n);
  }
  decay.series = {decay_recorded, decay_simulated};
  decay.references = {{0.83, "Housner (1963)"}};
  report.add_figure(svg::render(decay), "Ratio of angular velocity after to before each impact.");

  report.add_section("Errors");
  report.add_table({"Simulation against recording",
                    {"channel", "RMS error", "peak error", "unit"},
                    {{text_cell("rock_x"), number_cell(0.00312, 3), number_cell(0.0101, 3), text_cell("rad")},
                     {text_cell("slide_x"), number_cell(2.4, 3), number_cell(2.4, 3, CellMark::bad),
                      text_cell("mm")}}});
  return report;
}

class ReportInChromium : public testing::Test {
 protected:
  void SetUp() override {
    if (!chromium_installed())
      GTEST_SKIP() << "chromium is not installed (Debian package 'chromium'; scripts/setup.sh installs it)";
    dir_ = fs::temp_directory_path() / ("freestand_report_chromium_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

TEST_F(ReportInChromium, ScreenshotShowsEveryPlot) {
  const fs::path html = dir_ / "report.html", png = dir_ / "screenshot.png";
  synthetic_report().write(html.string());
  const std::string failure = chromium_screenshot(html, png, dir_, 1200, 3000);
  ASSERT_TRUE(failure.empty()) << failure;
  if (const char* keep = std::getenv("FREESTAND_REPORT_EXAMPLE_DIR")) {
    fs::copy_file(html, fs::path(keep) / "report-example.html", fs::copy_options::overwrite_existing);
    fs::copy_file(png, fs::path(keep) / "report-example.png", fs::copy_options::overwrite_existing);
  }

  const Screenshot shot(png);
  ASSERT_EQ(shot.width(), 1200);
  ASSERT_EQ(shot.height(), 3000);
  long inked = 0;
  for (int y = 0; y < shot.height(); ++y)
    for (int x = 0; x < shot.width(); ++x) inked += !near(shot.at(x, y), {255, 255, 255}, 10);
  EXPECT_GT(inked, 0.02 * shot.width() * shot.height()) << "screenshot nearly blank";

  const std::vector<Box> frames = find_frames(shot);
  ASSERT_EQ(frames.size(), 4u) << "one frame per figure expected";
  const Rgb recorded = parse_colour(svg::palette()[0]), simulated = parse_colour(svg::palette()[1]);

  // Rocking: both lines run across the record, the recorded one not in its gap.
  const Box& rock = frames[0];
  EXPECT_EQ(slices_showing(shot, rock, simulated, 0, kDuration, kDuration), 1);
  EXPECT_EQ(slices_showing(shot, rock, recorded, 0, kGapStart, kDuration), 1);
  EXPECT_EQ(slices_showing(shot, rock, recorded, kGapEnd, kDuration, kDuration), 1);
  EXPECT_EQ(pixels_showing(shot, rock, recorded, kGapStart + 0.05, kGapEnd - 0.05, kDuration), 0);

  // Sliding: both ramps (apart once the recorded one starts; at rest the
  // simulated line, drawn last, covers the recorded one).
  EXPECT_EQ(slices_showing(shot, frames[1], simulated, 0, kDuration, kDuration), 1);
  EXPECT_EQ(slices_showing(shot, frames[1], recorded, kRecordedSlideStart + 0.5, kDuration, kDuration), 1);

  // Modal diagram: the path's first and last colours of the time scale.
  EXPECT_GT(pixels_showing(shot, frames[2], {68, 1, 84}), 20) << "early (dark violet) part missing";
  EXPECT_GT(pixels_showing(shot, frames[2], {178, 221, 44}), 20) << "late (yellow-green) part missing";

  // Impact decay: twelve markers per series (a marker covers ~30 pixels).
  EXPECT_GT(pixels_showing(shot, frames[3], recorded), 12 * 15);
  EXPECT_GT(pixels_showing(shot, frames[3], simulated), 12 * 15);

  // The table's highlighted cell.
  long highlighted = 0;
  for (int y = frames[3].bottom; y < shot.height(); ++y)
    for (int x = 0; x < shot.width(); ++x) highlighted += near(shot.at(x, y), {251, 213, 189}, 3);
  EXPECT_GT(highlighted, 200) << "highlighted table cell not found below the last figure";
}

}  // namespace
}  // namespace freestand
