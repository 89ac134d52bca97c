#include "diagnosis_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>

#include "freestand/body_channels.h"
#include "svg_plot.h"

namespace freestand::diagnosis {

namespace {

const int kOverlays = 3;  // channels overlaid: the first mismatched ones

CellMark z_mark(double z, double threshold) { return std::abs(z) > threshold ? CellMark::bad : CellMark::good; }

// A channel of one recording: `recording` indexes Diagnosis::recorded (and the runs).
struct OverlaidChannel {
  std::size_t recording = 0;
  std::string channel;  // "body.rock_x"
  std::string title;    // as the features name it: "r2:body.rock_x" with several recordings
};

// The channel a feature is read from: "[rN:]body.CH.rest" -> CH; a launched body's touchdowns
// and bounces are read from its uplift; body-wide features (total_slip, rest.time) from none.
std::optional<OverlaidChannel> channel_of_feature(const std::string& feature) {
  OverlaidChannel c;
  std::string name = feature;
  if (name.size() > 1 && name[0] == 'r' && std::isdigit(static_cast<unsigned char>(name[1]))) {
    const std::size_t colon = name.find(':');
    c.recording = std::stoul(name.substr(1, colon - 1)) - 1;
    name = name.substr(colon + 1);
  }
  const std::size_t dot = name.find('.');
  const std::string body = name.substr(0, dot), rest = name.substr(dot + 1);
  const std::string first = rest.substr(0, rest.find('.'));
  const auto& channels = channel_names();
  if (std::find(channels.begin(), channels.end(), first) != channels.end()) c.channel = body + "." + first;
  else if (first.rfind("touchdown", 0) == 0 || first.rfind("bounce", 0) == 0) c.channel = body + ".uplift";
  else return std::nullopt;
  c.title = feature.substr(0, feature.size() - name.size()) + c.channel;
  return c;
}

// The channels of the first mismatched features, in time order.
std::vector<OverlaidChannel> mismatched_channels(const Diagnosis& d) {
  std::vector<OverlaidChannel> out;
  for (const Mismatch& m : d.mismatches) {
    const std::optional<OverlaidChannel> c = channel_of_feature(m.feature);
    if (!c) continue;
    if (std::none_of(out.begin(), out.end(), [&](const OverlaidChannel& o) { return o.title == c->title; }))
      out.push_back(*c);
    if (static_cast<int>(out.size()) == kOverlays) break;
  }
  return out;
}

std::string overlay(const Diagnosis& d, const OverlaidChannel& o) {
  const std::string& channel = o.channel;
  svg::LinePlot plot;
  plot.title = o.title;
  plot.x = {"t", "s", {}, {}};
  const bool angle = channel.find("rock") != std::string::npos || channel.find("twist") != std::string::npos;
  plot.y = {channel.substr(channel.find('.') + 1), angle ? "rad" : "m", {}, {}};
  auto add = [&](const std::vector<Recording>& runs, const char* label, bool dashed) {
    if (o.recording >= runs.size()) return;
    const Recording& r = runs[o.recording];
    if (const RecordingChannel* c = r.find(channel)) plot.series.push_back({label, r.time, c->values, dashed});
  };
  add(d.recorded, "recorded", false);
  add(d.simulated_nominal, "model as given", true);
  if (!d.effects.empty()) add(d.simulated_final, "improved model", false);
  for (const ChannelDivergence& c : d.divergence)  // named without the recording: marked for one recording only
    if (d.recorded.size() == 1 && c.channel == channel && std::isfinite(c.time)) plot.markers.push_back({c.time, "diverges"});
  return svg::render(plot);
}

// An effect's quick profile and refinements: the misfit of each point (the profile's members, on
// the fit window) against the value, a log-scale parameter on log10 of it; the nominal and the
// value named marked. A point whose run failed is left out.
std::string profile_figure(const Effect& e) {
  const Candidate& c = e.fit.candidate;
  const auto x_of = [&](double v) { return c.log_scale ? std::log10(v) : v; };
  svg::LinePlot plot;
  plot.title = fmt::format("{}: profile", c.name);
  plot.x = {c.log_scale ? "log10 " + c.entry : c.entry, c.unit, {}, {}};
  plot.y = {"misfit chi2", "", {}, {}};
  svg::Series points{"profile points", {}, {}, false};
  for (const auto& [value, chi2] : e.fit.profile)
    if (std::isfinite(chi2)) points.x.push_back(x_of(value)), points.y.push_back(chi2);
  plot.series.push_back(points);
  plot.markers = {{x_of(c.nominal), "model as given"}, {x_of(e.fit.value), "named"}};
  return svg::render(plot);
}

// The ensemble members of each model a drop is over ("profile": the quick profile's runs).
TableCell members_cell(const FittedCandidate& f) {
  return text_cell(f.members > 0 ? fmt::format("{}", f.members) : "profile");
}

Table candidate_table(const Diagnosis& d, std::size_t round) {
  Table t;
  t.caption = fmt::format("Round {}: every candidate's 1-D profile fit (one tested on its ensemble: the drop over every "
                          "feature, held-out part apart; one only profiled: its profile's drop, on the fit window when "
                          "there is one, and no held-out figure)", round + 1);
  t.header = {"candidate", "value", "nominal", "delta chi2", "its Monte Carlo s.e.", "members", "p", "delta BIC",
              "held-out delta chi2"};
  std::set<std::string> accepted;
  for (const Effect& e : d.effects) accepted.insert(e.fit.candidate.name);
  for (const FittedCandidate& f : d.rounds[round]) {
    const CellMark mark = accepted.count(f.candidate.name) ? CellMark::good : CellMark::none;
    t.rows.push_back({text_cell(f.candidate.name, mark), number_cell(f.value), number_cell(f.candidate.nominal),
                      number_cell(f.delta), number_cell(f.delta_se), members_cell(f), number_cell(f.p_value, 2),
                      number_cell(f.delta_bic), number_cell(f.held_out_delta)});
  }
  return t;
}

Table hypothesis_table(const Diagnosis& d) {
  Table t;
  t.caption = "Hypotheses (--hypothesis): the model as given with the stated value, on its own ensemble";
  t.header = {"candidate", "value", "nominal", "delta chi2", "its Monte Carlo s.e.", "members", "p",
              "delta BIC", "held-out delta chi2", "against the improved model"};
  for (const HypothesisTest& h : d.hypotheses) {
    const FittedCandidate& f = h.fit;
    t.rows.push_back({text_cell(f.candidate.name, h.supported ? CellMark::good : CellMark::none), number_cell(f.value),
                      number_cell(f.candidate.nominal), number_cell(f.delta), number_cell(f.delta_se),
                      members_cell(f), number_cell(f.p_value, 2), number_cell(f.delta_bic), number_cell(f.held_out_delta),
                      text_cell(h.against_improved)});
  }
  return t;
}

Table feature_table(const Diagnosis& d, double threshold) {
  Table t;
  t.caption = fmt::format("Event features: recorded against the model as given and improved (ensemble means; n/a: "
                          "the event is absent); z of the event's existence and value, beyond {} marked", threshold);
  t.header = {"feature", "t (s)", "held out", "recorded", "as given", "z", "improved", "z"};
  for (const FeatureRow& f : d.features) {
    const double z0 = f.z_nominal, z1 = f.z_improved;
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
  for (const OverlaidChannel& o : mismatched_channels(d))
    report.add_figure(overlay(d, o), o.title + ": the recording (corrected for accepted measurement issues), "
                                               "the model as given (dashed) and the improved model");
  report.add_section("Candidates");
  for (const Effect& e : d.effects)
    if (e.fit.profile.size() > 1)
      report.add_figure(profile_figure(e), e.fit.candidate.name + ": the misfit along its profile (one run per point "
                                           "unless --profile-members says more, on the fit window), the value named "
                                           "after the ensemble test");
  for (std::size_t r = 0; r < d.rounds.size(); ++r) report.add_table(candidate_table(d, r));
  if (!d.hypotheses.empty()) report.add_table(hypothesis_table(d));
  report.add_section("Event features");
  report.add_table(feature_table(d, d.z_threshold));
}

}  // namespace freestand::diagnosis
