// The diagnosis report overlays the channel a mismatched feature is read from, of the
// recording the feature belongs to (features of several recordings are named "rN:...").

#include "diagnosis_report.h"

#include <gtest/gtest.h>

#include <regex>

namespace freestand::diagnosis {
namespace {

Recording run(const std::string& channel, double level) {
  Recording r;
  r.time = {0, 0.1, 0.2, 0.3};
  r.channels.push_back({channel, {level, level + 0.01, level, level}, false});
  return r;
}

int count_lines(const std::string& html) {
  const std::regex line("stroke-linejoin=\"round\"");
  return static_cast<int>(std::distance(std::sregex_iterator(html.begin(), html.end(), line), std::sregex_iterator()));
}

TEST(DiagnosisReport, OverlaysTheChannelOfTheMismatchedFeatureOfItsRecording) {
  Diagnosis d;
  // Two recordings of a tossed cube: the second one's first bounce is mismatched; it is read
  // from the cube's uplift of recording 2.
  d.recorded = {run("cube.uplift", 0.0), run("cube.uplift", 0.5)};
  d.simulated_nominal = {run("cube.uplift", 0.1), run("cube.uplift", 0.6)};
  d.mismatches.push_back({"r2:cube.bounce1.height", "r2:cube", "uplift", 0.1, 0.02, 0.0, 9});
  d.mismatches.push_back({"r2:cube.total_slip", "r2:cube", "slide", 0.2, 0.02, 0.0, 9});  // body-wide: no channel
  HtmlReport report("diagnosis");
  add_diagnosis_sections(report, d);
  const std::string html = report.html();
  EXPECT_NE(html.find("r2:cube.uplift"), std::string::npos);
  EXPECT_EQ(html.find("r2:cube.bounce1"), html.find("r2:cube.bounce1.height")) << "no overlay of a non-channel";
  EXPECT_EQ(count_lines(html), 2) << "recording 2 and its model as given: one overlay, two lines";
}

}  // namespace
}  // namespace freestand::diagnosis
