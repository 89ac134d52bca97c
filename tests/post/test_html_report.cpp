// HtmlReport: number formatting, structure, self-containment, atomic write.

#include "html_report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "freestand/input_error.h"
#include "svg_plot.h"

namespace freestand {
namespace {

namespace fs = std::filesystem;

TEST(FormatNumber, SignificantDigits) {
  EXPECT_EQ(format_number(1234.5678, 4), "1235");
  EXPECT_EQ(format_number(0.012345, 3), "0.0123");
  EXPECT_EQ(format_number(-2.5, 2), "\u22122.5");
  EXPECT_EQ(format_number(0, 3), "0");
  EXPECT_EQ(format_number(1.5e-5, 3), "1.50e-05");
  EXPECT_EQ(format_number(2.5e7, 2), "2.5e+07");
  EXPECT_EQ(format_number(std::numeric_limits<double>::quiet_NaN(), 3), "n/a");
}

HtmlReport sample_report() {
  HtmlReport report("Block <A> on the shake table");
  report.add_metadata("recording", "cube_toss_03.h5");
  report.add_section("Table motion");
  report.add_paragraph("Peak & duration");
  report.add_section("Errors");
  report.add_table({"Errors against the recording",
                    {"channel", "RMS error"},
                    {{text_cell("rock_x"), number_cell(0.01234, 3, CellMark::bad)},
                     {text_cell("slide_x"), number_cell(0.5, 2, CellMark::good)}}});
  svg::PointPlot plot;
  plot.series = {{"simulated", {1, 2}, {0.9, 0.8}}};
  report.add_figure(svg::render(plot), "Impact decay");
  return report;
}

TEST(HtmlReport, StructureNumberingAndEscaping) {
  const std::string html = sample_report().html();
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("<title>Block &lt;A&gt; on the shake table</title>"), std::string::npos);
  EXPECT_NE(html.find("<th>recording</th><td>cube_toss_03.h5</td>"), std::string::npos);
  EXPECT_NE(html.find("<h2>1. Table motion</h2>"), std::string::npos);
  EXPECT_NE(html.find("<h2>2. Errors</h2>"), std::string::npos);
  EXPECT_NE(html.find("href=\"#s2\""), std::string::npos);
  EXPECT_NE(html.find("<p>Peak &amp; duration</p>"), std::string::npos);
  EXPECT_NE(html.find("<b>Table 1.</b> Errors against the recording"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"num bad\">0.0123</td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"num good\">0.50</td>"), std::string::npos);
  EXPECT_NE(html.find("<b>Figure 1.</b> Impact decay"), std::string::npos);
  // The second section holds the table and the figure, after its heading.
  EXPECT_LT(html.find("<h2>2. Errors</h2>"), html.find("<table>"));
}

TEST(HtmlReport, ReferencesNothingOutsideItself) {
  const std::string html = sample_report().html();
  for (const char* outside : {"http:", "https:", "//", "<script", "src=", "url(", "@import", "<link"})
    EXPECT_EQ(html.find(outside), std::string::npos) << outside;
}

TEST(HtmlReport, RowLengthMismatchNamesTableAndRow) {
  HtmlReport report("r");
  try {
    report.add_table({"errors", {"a", "b"}, {{text_cell("1"), text_cell("2")}, {text_cell("3")}}});
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'errors', row 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(report.add_figure("<div>", "not svg"), std::invalid_argument);
}

class HtmlReportWrite : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("freestand_html_report_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string read(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  fs::path dir_;
};

TEST_F(HtmlReportWrite, ReplacesTheFileAndLeavesNoTemporary) {
  const fs::path path = dir_ / "report.html";
  {
    std::ofstream old(path);
    old << "old report";
  }
  const HtmlReport report = sample_report();
  report.write(path.string());
  EXPECT_EQ(read(path), report.html());
  EXPECT_FALSE(fs::exists(path.string() + ".part"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(HtmlReportWrite, UnwritablePlaceNamesThePath) {
  const fs::path path = dir_ / "missing" / "report.html";
  try {
    sample_report().write(path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  // A directory in the way of the rename: the temporary is removed, the directory kept.
  const fs::path blocked = dir_ / "blocked.html";
  fs::create_directories(blocked / "inside");
  EXPECT_THROW(sample_report().write(blocked.string()), InputError);
  EXPECT_TRUE(fs::is_directory(blocked));
  EXPECT_FALSE(fs::exists(blocked.string() + ".part"));
}

}  // namespace
}  // namespace freestand
