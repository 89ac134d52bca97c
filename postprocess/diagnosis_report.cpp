#include "diagnosis_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "svg_plot.h"

namespace freestand::diagnosis {

namespace {

const int kOverlays = 3;  // channels overlaid: the first mismatched ones

CellMark z_mark(double z, double threshold) { return std::abs(z) > threshold ? CellMark::bad : CellMark::good; }

// The channels ("body.rock_x") of the first mismatched features, in time order.
std::vector<std::string> mismatched_channels(const Diagnosis& d) {
  std::vector<std::string> out;
  for (const Mismatch& m : d.mismatches) {
    const std::size_t body = m.feature.find('.'), channel = m.feature.find('.', body + 1);
    if (channel == std::string::npos) continue;  // a body-wide feature (total_slip, motion_onset)
    const std::string name = m.feature.substr(0, channel);
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
    if (static_cast<int>(out.size()) == kOverlays) break;
  }
  return out;
}

std::string overlay(const Diagnosis& d, const std::string& channel) {
  svg::LinePlot plot;
  plot.title = channel;
  plot.x = {"t", "s", {}, {}};
  const bool angle = channel.find("rock") != std::string::npos || channel.find("twist") != std::string::npos;
  plot.y = {channel.substr(channel.find('.') + 1), angle ? "rad" : "m", {}, {}};
  auto add = [&](const std::vector<Recording>& runs, const char* label, bool dashed) {
    for (const Recording& r : runs)
      if (const RecordingChannel* c = r.find(channel)) plot.series.push_back({label, r.time, c->values, dashed});
  };
  add(d.recorded, "recorded", false);
  add(d.simulated_nominal, "model as given", true);
  if (!d.effects.empty()) add(d.simulated_final, "improved model", false);
  for (const ChannelDivergence& c : d.divergence)
    if (c.channel == channel && std::isfinite(c.time)) plot.markers.push_back({c.time, "diverges"});
  return svg::render(plot);
}

Table candidate_table(const Diagnosis& d, std::size_t round) {
  Table t;
  t.caption = fmt::format("Round {}: every candidate's 1-D profile fit", round + 1);
  t.header = {"candidate", "value", "nominal", "delta chi2", "p", "delta BIC", "held-out delta chi2"};
  std::set<std::string> accepted;
  for (const Effect& e : d.effects) accepted.insert(e.fit.candidate.name);
  for (const FittedCandidate& f : d.rounds[round]) {
    const CellMark mark = accepted.count(f.candidate.name) ? CellMark::good : CellMark::none;
    t.rows.push_back({text_cell(f.candidate.name, mark), number_cell(f.value), number_cell(f.candidate.nominal),
                      number_cell(f.delta), number_cell(f.p_value, 2), number_cell(f.delta_bic),
                      number_cell(f.held_out_delta)});
  }
  return t;
}

Table feature_table(const Diagnosis& d, double threshold) {
  Table t;
  t.caption = fmt::format("Event features: recorded against the model as given and improved; z = (recorded - "
                          "simulated) / s.d., beyond {} marked", threshold);
  t.header = {"feature", "t (s)", "held out", "recorded", "as given", "z", "improved", "z"};
  for (const FeatureRow& f : d.features) {
    const double z0 = (f.recorded - f.nominal) / f.sd, z1 = (f.recorded - f.improved) / f.sd;
    t.rows.push_back({text_cell(f.name), number_cell(f.time, 3), text_cell(f.held_out ? "yes" : ""),
                      number_cell(f.recorded), number_cell(f.nominal), number_cell(z0, 2, z_mark(z0, threshold)),
                      number_cell(f.improved), number_cell(z1, 2, z_mark(z1, threshold))});
  }
  return t;
}

}  // namespace

void add_diagnosis_sections(HtmlReport& report, const Diagnosis& d) {
  report.add_section("Diagnosis");
  std::istringstream lines(d.verdict);
  for (std::string line; std::getline(lines, line);) report.add_paragraph(line);
  for (const MeasurementIssue& m : d.measurement) report.add_paragraph("Measurement issue: " + m.text);
  report.add_section("Before and after");
  for (const std::string& channel : mismatched_channels(d))
    report.add_figure(overlay(d, channel), channel + ": the recording (corrected for accepted measurement issues), "
                                                     "the model as given (dashed) and the improved model");
  report.add_section("Candidates");
  for (std::size_t r = 0; r < d.rounds.size(); ++r) report.add_table(candidate_table(d, r));
  report.add_section("Event features");
  report.add_table(feature_table(d, d.z_threshold));
}

}  // namespace freestand::diagnosis
