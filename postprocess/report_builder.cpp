#include "report_builder.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "freestand/body_channels.h"
#include "svg_plot.h"

namespace freestand {

namespace fs = std::filesystem;
using analysis::kChannelCount;
using analysis::kNaN;

namespace {

constexpr double kGravity = 9.80665;  // m/s^2, standard gravity: PGA in g
// Impact decay axes stop here: a ratio above 1 means the impact gained angular velocity (the
// table can drive it), far above it the half-cycle was too small for its rates to be resolved.
constexpr double kMaxRatioShown = 1.5;
constexpr std::size_t kMaxSlipRows = 40;  // longer slip tables are cut (the JSON of `compare` and /events hold all)

// Channels are shown in rad (angles) and mm (lengths).
bool is_angle(int channel) { return channel <= analysis::kTwist; }
double display_scale(int channel) { return is_angle(channel) ? 1.0 : 1e3; }
const char* display_unit(int channel) { return is_angle(channel) ? "rad" : "mm"; }
const std::string& channel_name(int channel) { return channel_names()[channel]; }

TableCell count_cell(std::size_t n) { return {std::to_string(n), true, CellMark::none}; }

svg::Series scaled(std::string label, const std::vector<double>& x, const std::vector<double>& y, double scale) {
  svg::Series s{std::move(label), x, y};
  for (double& v : s.y) v *= scale;
  return s;
}

const svg::Axis kTime{"t", "s", {}, {}};

double duration(const Results& r) { return r.time.back() - r.time.front(); }

// The recorded counterpart of a simulated body, or null.
const ComparedBody* compared(const ReportData& data, const std::string& body) {
  if (!data.comparison) return nullptr;
  for (const ComparedBody& b : data.comparison->bodies)
    if (b.simulated.name == body) return &b;
  return nullptr;
}

bool moved(const AnalysedBody& sim, const ComparedBody* rec, int channel, const analysis::AnalysisParameters& p) {
  return rec ? channel_moved(*rec, channel, p) : channel_moved(sim, channel, p);
}

std::string describe_metadata(const std::string& text) { return text.empty() ? "n/a" : text; }

void add_metadata(HtmlReport& report, const ReportData& data) {
  const Results& r = data.results;
  const nlohmann::json& s = r.scenario;
  if (s.is_object() && s.contains("description")) report.add_metadata("scenario", s["description"].get<std::string>());
  if (s.is_object() && s.contains("ground_motion"))
    report.add_metadata("ground motion", s["ground_motion"].get<std::string>());
  report.add_metadata("results", r.path);
  if (data.recording) {
    const std::string source = data.recording->nominal.value("source", "");
    report.add_metadata("recording", data.recording->path + (source.empty() ? "" : " (" + source + ")"));
  }
  const auto attribute = [&](const char* key) {
    const auto it = r.attributes.find(key);
    return describe_metadata(it == r.attributes.end() ? "" : it->second);
  };
  report.add_metadata("versions", fmt::format("freestand {}, LIGGGHTS {}", attribute("freestand_version"),
                                              attribute("liggghts_version")));
  report.add_metadata("time step", r.time_step() > 0 ? fmt::format("{:.4g} s", r.time_step()) : "n/a");
  report.add_metadata("duration", fmt::format("{:.2f} s simulated, {} samples ({:.0f} Hz output)", duration(r),
                                              r.time.size(), (r.time.size() - 1) / duration(r)));
  std::vector<std::string> bodies;
  for (const AnalysedBody& b : data.bodies) bodies.push_back(fmt::format("{} (on {})", b.name, b.supported_by));
  report.add_metadata("bodies", fmt::format("{}", fmt::join(bodies, ", ")));
}

// Seconds per mode of motion.
std::map<analysis::Mode, double> mode_seconds(const analysis::MotionSummary& s) {
  std::map<analysis::Mode, double> seconds;
  for (const analysis::ModeSegment& m : s.modes) seconds[m.mode] += m.end - m.start;
  return seconds;
}

void add_summary(HtmlReport& report, const ReportData& data) {
  report.add_section("Summary");
  Table t{"What each body did (simulation). Peak |rock|, |slide|: the larger of the x and y channels; impacts and ratios: of the axis with more impacts.",
          {"body", "overturned", "peak |rock| (rad)", "peak |slide| (mm)", "peak uplift (mm)", "rocking (s)",
           "sliding (s)", "impacts", "median ω ratio", "Housner r", "slip events"},
          {}};
  for (const AnalysedBody& b : data.bodies) {
    const analysis::MotionSummary& s = b.summary;
    auto seconds = mode_seconds(s);
    const int axis = s.impacts[1].impacts.size() > s.impacts[0].impacts.size() ? 1 : 0;
    const analysis::Overturn& o = s.overturn;
    t.rows.push_back({text_cell(b.name),
                      text_cell(o.overturned ? fmt::format("yes, at {:.2f} s", o.time) : "no",
                                o.overturned ? CellMark::bad : CellMark::none),
                      number_cell(std::max(s.peaks[analysis::kRockX].magnitude(), s.peaks[analysis::kRockY].magnitude())),
                      number_cell(1e3 * std::max(s.peaks[analysis::kSlideX].magnitude(),
                                                 s.peaks[analysis::kSlideY].magnitude())),
                      number_cell(1e3 * s.peaks[analysis::kUplift].max),
                      number_cell(seconds[analysis::Mode::rock] + seconds[analysis::Mode::slide_rock], 3),
                      number_cell(seconds[analysis::Mode::slide] + seconds[analysis::Mode::slide_rock], 3),
                      count_cell(s.impacts[axis].impacts.size()),
                      number_cell(s.impacts[axis].median_ratio, 3),
                      number_cell(s.impacts[axis].housner_ratio, 3),
                      count_cell(s.slips.size())});
  }
  report.add_table(t);
}

void add_table_motion(HtmlReport& report, const ReportData& data) {
  const Results& r = data.results;
  report.add_section("Table motion");
  std::vector<std::string> axes;
  for (const char* axis : {"x", "y", "z"}) {
    const auto d = r.table.find(std::string("d") + axis);
    if (d != r.table.end() && std::any_of(d->second.begin(), d->second.end(), [](double v) { return v != 0.0; }))
      axes.push_back(axis);
  }
  if (axes.empty()) {
    report.add_paragraph("The table does not move.");
    return;
  }
  svg::LinePlot acceleration{"Table acceleration", kTime, {"a", "m/s²", {}, {}}, {}, {}, "", {}, "", {880, 300}};
  svg::LinePlot displacement{"Table displacement", kTime, {"d", "mm", {}, {}}, {}, {}, "", {}, "", {880, 300}};
  Table peaks{"Peak table motion (simulation input).", {"axis", "PGA (m/s²)", "PGA (g)", "PGV (m/s)", "PGD (mm)"}, {}};
  const auto peak = [](const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
  };
  for (const std::string& axis : axes) {
    const std::vector<double>&a = r.table.at("a" + axis), &v = r.table.at("v" + axis), &d = r.table.at("d" + axis);
    acceleration.series.push_back(scaled("a" + axis + " simulated", r.time, a, 1));
    displacement.series.push_back(scaled("d" + axis + " simulated", r.time, d, 1e3));
    peaks.rows.push_back({text_cell(axis), number_cell(peak(a)), number_cell(peak(a) / kGravity),
                          number_cell(peak(v)), number_cell(1e3 * peak(d))});
  }
  if (data.recording)
    for (const std::string& axis : axes) {
      if (const auto* a = data.recording->table_channel('a', axis[0]))
        acceleration.series.push_back(scaled("a" + axis + " recorded", data.recording->time, *a, 1));
      if (const auto* d = data.recording->table_channel('d', axis[0]))
        displacement.series.push_back(scaled("d" + axis + " recorded", data.recording->time, *d, 1e3));
    }
  report.add_table(peaks);
  report.add_figure(svg::render(acceleration), "Acceleration of the table.");
  report.add_figure(svg::render(displacement), "Displacement of the table.");
}

void add_body_tables(HtmlReport& report, const AnalysedBody& b, const ComparedBody* rec) {
  const analysis::MotionSummary& s = b.summary;
  Table peaks{fmt::format("Peaks and residual offsets of {} (residual: mean from {:.2f} s to the end).", b.name,
                          s.residual.window_start),
              {"channel", "unit", "max", "at (s)", "min", "at (s)", "residual"},
              {}};
  if (rec) peaks.header.insert(peaks.header.end(), {"recorded |peak|", "recorded residual"});
  for (int c = 0; c < kChannelCount; ++c) {
    const double k = display_scale(c);
    const analysis::Peak& p = s.peaks[c];
    std::vector<TableCell> row{text_cell(channel_name(c)), text_cell(display_unit(c)), number_cell(k * p.max),
                               number_cell(p.t_max), number_cell(k * p.min), number_cell(p.t_min),
                               number_cell(k * s.residual.mean[c], 3)};
    if (rec) {
      row.push_back(number_cell(k * rec->recorded.summary.peaks[c].magnitude()));
      row.push_back(number_cell(k * rec->recorded.summary.residual.mean[c], 3));
    }
    peaks.rows.push_back(std::move(row));
  }
  report.add_table(peaks);
  report.add_paragraph(s.overturn.overturned
                           ? fmt::format("{} overturned at {:.3f} s ({}).", b.name, s.overturn.time,
                                         s.overturn.criterion)
                           : fmt::format("{} did not overturn.", b.name));
  if (s.slips.empty()) return;
  Table slips{fmt::format("Slip events of {} (slide relative to its support, rocking removed).", b.name),
              {"#", "onset (s)", "stop (s)", "slip x (mm)", "slip y (mm)", "peak speed (m/s)"},
              {}};
  for (std::size_t i = 0; i < s.slips.size() && i < kMaxSlipRows; ++i) {
    const analysis::SlipEvent& e = s.slips[i];
    slips.rows.push_back({count_cell(i + 1), number_cell(e.onset), number_cell(e.stop),
                          number_cell(1e3 * e.slip_x, 3), number_cell(1e3 * e.slip_y, 3), number_cell(e.peak_speed, 3)});
  }
  if (s.slips.size() > kMaxSlipRows)
    slips.caption += fmt::format(" First {} of {} shown.", kMaxSlipRows, s.slips.size());
  report.add_table(slips);
}

// One row per mode that occurs, simulated and (with a recording) recorded.
void add_mode_timeline(HtmlReport& report, const AnalysedBody& b, const ComparedBody* rec, double end) {
  using analysis::Mode;
  static const std::map<Mode, std::string> colours{
      {Mode::rest, "#A0A0A0"}, {Mode::rock, svg::palette()[0]}, {Mode::slide, svg::palette()[1]},
      {Mode::slide_rock, svg::palette()[3]}, {Mode::twist, svg::palette()[2]}, {Mode::flight, svg::palette()[4]},
      {Mode::overturned, "#000000"}, {Mode::lost, "#DDDDDD"}};
  svg::TimelinePlot plot{fmt::format("Modes of motion of {}", b.name), {"t", "s", 0.0, end}, {}, 880};
  for (const auto& [mode, colour] : colours)
    for (const AnalysedBody* body : {&b, rec ? &rec->recorded : nullptr}) {
      if (!body) continue;
      svg::TimelineRow row{std::string(analysis::mode_name(mode)) + (rec ? (body == &b ? " (sim)" : " (rec)") : ""),
                           {}, colour};
      for (const analysis::ModeSegment& m : body->summary.modes)
        if (m.mode == mode) row.spans.emplace_back(m.start, m.end);
      if (!row.spans.empty()) plot.rows.push_back(std::move(row));
    }
  report.add_figure(svg::render(plot), fmt::format("Modes of motion of {} over time{}.", b.name,
                                                   rec ? ", simulated (sim) and recorded (rec)" : ""));
}

void add_time_histories(HtmlReport& report, const AnalysedBody& b, const ComparedBody* rec,
                        const analysis::AnalysisParameters& parameters, double end) {
  std::vector<std::string> still;
  for (int c = 0; c < kChannelCount; ++c) {
    if (!moved(b, rec, c, parameters)) {
      still.push_back(channel_name(c));
      continue;
    }
    const double k = display_scale(c);
    svg::LinePlot plot{fmt::format("{} of {}", channel_name(c), b.name), {"t", "s", 0.0, end},
                       {channel_name(c), display_unit(c), {}, {}}, {}, {}, "", {}, "", {880, 280}};
    plot.series.push_back(scaled("simulated", b.motion.time, b.motion.channels[c], k));
    std::string caption = fmt::format("{} of {}", channel_name(c), b.name);
    if (rec && !rec->recorded.motion.channels[c].empty()) {
      plot.series.push_back(scaled("recorded", rec->recorded.motion.time, rec->recorded.motion.channels[c], k));
      caption += ", simulated and recorded (gaps: lost samples)";
      const double diverged = rec->comparison.channels[c].divergence_time;
      if (std::isfinite(diverged)) {
        plot.windows.push_back({diverged, end, fmt::format("diverged at {:.2f} s", diverged)});
        plot.windows_legend = "after divergence";
      }
    }
    if (c == analysis::kRockX || c == analysis::kRockY) {
      for (const analysis::Impact& i : b.summary.impacts[c].impacts) plot.markers.push_back({i.time, ""});
      if (!plot.markers.empty()) {
        plot.markers_legend = "impact (simulated)";
        caption += fmt::format("; dashed lines: the {} simulated impacts", plot.markers.size());
      }
    }
    report.add_figure(svg::render(plot), caption + ".");
  }
  if (!still.empty())
    report.add_paragraph(fmt::format("Not plotted: {} stay within {:g} rad / {:g} mm (the analysis' resolution, "
                                     "{:g} noise standard deviations) throughout.",
                                     fmt::join(still, ", "), parameters.threshold_sigmas * parameters.angle_noise,
                                     1e3 * parameters.threshold_sigmas * parameters.length_noise,
                                     parameters.threshold_sigmas));
}

// Modal-interaction diagrams (rock-slide, slide-twist, rock-twist) on the
// dominant rocking and sliding axes, coloured by time.
void add_modal_diagrams(HtmlReport& report, const AnalysedBody& b, const ComparedBody* rec,
                        const analysis::AnalysisParameters& parameters) {
  const auto larger = [&](int first, int second) {
    return b.summary.peaks[second].magnitude() > b.summary.peaks[first].magnitude() ? second : first;
  };
  const int rock = larger(analysis::kRockX, analysis::kRockY), slide = larger(analysis::kSlideX, analysis::kSlideY);
  std::vector<std::string> omitted;
  for (auto [x, y] : {std::pair{slide, rock}, std::pair{slide, int(analysis::kTwist)},
                      std::pair{int(analysis::kTwist), rock}}) {
    const std::string name = fmt::format("{} against {}", channel_name(y), channel_name(x));
    if (!moved(b, rec, x, parameters) || !moved(b, rec, y, parameters)) {
      omitted.push_back(name);
      continue;
    }
    svg::TrajectoryPlot plot{fmt::format("{}: {}", b.name, name),
                             {channel_name(x), display_unit(x), {}, {}},
                             {channel_name(y), display_unit(y), {}, {}},
                             {scaled("simulated", b.motion.channels[x], b.motion.channels[y], 1)},
                             b.motion.time};
    for (double& v : plot.paths[0].x) v *= display_scale(x);
    for (double& v : plot.paths[0].y) v *= display_scale(y);
    if (rec && !rec->recorded.motion.channels[x].empty() && !rec->recorded.motion.channels[y].empty()) {
      svg::Series r{"recorded", rec->recorded.motion.channels[x], rec->recorded.motion.channels[y]};
      for (double& v : r.x) v *= display_scale(x);
      for (double& v : r.y) v *= display_scale(y);
      plot.paths.push_back(std::move(r));
    }
    report.add_figure(svg::render(plot),
                      fmt::format("Modal-interaction diagram of {}: {}; the simulated path coloured by time{}.",
                                  b.name, name, rec ? ", the recorded one plain" : ""));
  }
  if (!omitted.empty())
    report.add_paragraph(fmt::format("Diagrams omitted (a coordinate does not move): {}.", fmt::join(omitted, "; ")));
}

void add_impact_decay(HtmlReport& report, const AnalysedBody& b, const ComparedBody* rec) {
  for (int axis = 0; axis < 2; ++axis) {
    const analysis::RockingImpacts& sim = b.summary.impacts[axis];
    const std::vector<analysis::Impact>* recorded = rec ? &rec->recorded.summary.impacts[axis].impacts : nullptr;
    if (sim.impacts.empty() && (!recorded || recorded->empty())) continue;
    svg::PointPlot plot{fmt::format("Impact decay of {} ({})", b.name, channel_name(axis)),
                        {"impact n", "", {}, {}}, {"ω after / ω before", "", {}, {}}, {}, {}};
    const auto ratios = [](std::string label, const std::vector<analysis::Impact>& impacts) {
      svg::Series s{std::move(label), {}, {}};
      for (std::size_t n = 0; n < impacts.size(); ++n) s.x.push_back(n + 1.0), s.y.push_back(impacts[n].ratio);
      return s;
    };
    plot.series.push_back(ratios("simulated", sim.impacts));
    if (recorded) plot.series.push_back(ratios("recorded", *recorded));
    if (std::isfinite(sim.housner_ratio))
      plot.references.push_back({sim.housner_ratio, fmt::format("Housner r = {:.3f}", sim.housner_ratio)});
    std::string caption = fmt::format(
        "Ratio of the angular velocity after to before each impact of {} in {}; simulated median {:.3f}", b.name,
        channel_name(axis), sim.median_ratio);
    if (recorded) caption += fmt::format(", recorded median {:.3f}", rec->recorded.summary.impacts[axis].median_ratio);
    std::size_t off_axis = 0, total = 0;
    for (const svg::Series& s : plot.series)
      for (double r : s.y) off_axis += r > kMaxRatioShown, total += std::isfinite(r);
    if (off_axis > 0) {
      plot.y.min = 0.0, plot.y.max = kMaxRatioShown;
      caption += fmt::format("; {} of {} ratios lie above {} (off the axis): impacts of half-cycles too small for the "
                             "angular velocity to be resolved",
                             off_axis, total, kMaxRatioShown);
    }
    if (std::isfinite(sim.housner_ratio))
      caption += "; dashed: Housner's r = 1 − 1.5 sin²α of a rectangular block on rigid ground";
    report.add_figure(svg::render(plot), caption + ".");
  }
}

void add_body(HtmlReport& report, const ReportData& data, const AnalysedBody& b) {
  const ComparedBody* rec = compared(data, b.name);
  const analysis::AnalysisParameters parameters = data.comparison ? data.comparison->parameters
                                                                  : analysis::AnalysisParameters{};
  const double end = data.results.time.back();
  report.add_section(fmt::format("Body '{}'", b.name));
  const analysis::BodyGeometry& g = b.geometry;
  if (g.known(0))
    report.add_paragraph(fmt::format(
        "{} stands on {}. Base half-widths b = {:.4g} m (x), {:.4g} m (y); centre of mass h = {:.4g} m above the base; "
        "slenderness α = {:.2f}° (x), {:.2f}° (y).",
        b.name, b.supported_by, g.half_width_x, g.half_width_y, g.com_height, g.slenderness(0) * 180 / M_PI,
        g.slenderness(1) * 180 / M_PI));
  add_body_tables(report, b, rec);
  add_mode_timeline(report, b, rec, end);
  add_time_histories(report, b, rec, parameters, end);
  add_modal_diagrams(report, b, rec, parameters);
  add_impact_decay(report, b, rec);
}

void add_energy(HtmlReport& report, const Results& r) {
  if (r.energy.empty()) return;
  report.add_section("Energy ledger");
  const auto& e = r.energy;
  const auto shifted = [&](const std::string& label, const std::string& key) {
    svg::Series s{label, r.time, e.at(key)};
    const double start = s.y.front();
    for (double& v : s.y) v -= start;
    return s;
  };
  svg::LinePlot plot{"Energy of the bodies", kTime, {"E", "J", {}, {}}, {}, {}, "", {}, "", {880, 360}};
  plot.series = {{"kinetic", r.time, e.at("kinetic")},
                 shifted("potential − start", "potential"),
                 {"elastic", r.time, e.at("elastic")},
                 {"normal dissipation", r.time, e.at("normal_dissipation")},
                 {"friction dissipation", r.time, e.at("friction_dissipation")},
                 {"table work", r.time, e.at("table_work")},
                 shifted("balance − start", "balance")};
  report.add_figure(svg::render(plot),
                    "Energy ledger of fix rigid/convex: balance = kinetic + potential + elastic + dissipated − table "
                    "work, constant while the ledger closes.");
  double drift = 0, work = 0;
  for (std::size_t k = 0; k < r.time.size(); ++k) {
    drift = std::max(drift, std::abs(e.at("balance")[k] - e.at("balance").front()));
    work = std::max(work, std::abs(e.at("table_work")[k]));
  }
  report.add_paragraph(fmt::format(
      "Largest drift of the balance: {:.4g} J{}.", drift,
      work > 0 ? fmt::format(", {:.2f} % of the largest table work ({:.4g} J)", 100 * drift / work, work) : ""));
}

void add_error_table(HtmlReport& report, const RunComparison& run) {
  report.add_section("Simulation against recording");
  std::vector<std::string> header{"body", "channel", "unit", "samples"};
  for (const Metric& m : error_metrics())
    header.push_back(std::string(m.heading) + (*m.unit ? fmt::format(" ({})", m.unit) : ""));
  Table table{"Errors per body and channel (channels that moved beyond the analysis' resolution in the simulation "
              "or the recording). Highlighted: the channel of each body that diverges first.",
              header, {}};
  std::vector<std::string> firsts;
  for (const ComparedBody& b : run.bodies) {
    const int first = first_divergence(b.comparison);
    if (first >= 0)
      firsts.push_back(fmt::format("{} in {} at {:.2f} s", b.simulated.name, channel_name(first),
                                   b.comparison.channels[first].divergence_time));
    for (int c = 0; c < kChannelCount; ++c) {
      const comparison::ChannelComparison& cc = b.comparison.channels[c];
      if (cc.samples == 0 || !channel_moved(b, c, run.parameters)) continue;
      std::vector<TableCell> row{text_cell(b.simulated.name), text_cell(channel_name(c)), text_cell(display_unit(c)),
                                 count_cell(cc.samples)};
      for (const Metric& m : error_metrics()) {
        const bool highlight = c == first && std::string(m.key) == "divergence_time";
        row.push_back(number_cell(m.value(cc) * (m.in_channel_units ? display_scale(c) : 1.0), 3,
                                  highlight ? CellMark::bad : CellMark::none));
      }
      table.rows.push_back(std::move(row));
    }
  }
  report.add_paragraph(
      "Peak error = 100 (simulated − recorded) / recorded peak; NRMSE = RMS difference / recorded peak; the time "
      "offset and gain fit recorded(t) ≈ gain · simulated(t − offset) + bias (a gain far from 1 or an offset far "
      "from 0 at high correlation points at the measurement rather than the model); a channel diverges where the "
      "RMS difference over 0.1 s exceeds max(4 noise, 10 % of the recorded peak). Definitions: "
      "docs/postprocessing.md.");
  report.add_table(table);
  report.add_paragraph(firsts.empty() ? "No channel diverges."
                                      : fmt::format("First divergence: {}.", fmt::join(firsts, "; ")));
  if (!run.unrecorded.empty())
    report.add_paragraph(fmt::format("Not in the recording (not compared): {}.", fmt::join(run.unrecorded, ", ")));
}

}  // namespace

ReportData load_report_data(const std::string& results_path, const std::string& recording_path) {
  ReportData data{read_results(results_path), {}, {}, {}};
  data.bodies = analyse_results(data.results);
  if (!recording_path.empty()) {
    data.recording = read_recording(recording_path);
    data.comparison = compare_run(data.bodies, *data.recording, results_path);
  }
  return data;
}

HtmlReport build_report(const ReportData& data) {
  const std::string run_name = fs::absolute(data.results.path).parent_path().filename().string();
  HtmlReport report(fmt::format("freestand report: {}{}", run_name, data.recording ? " against its recording" : ""));
  add_metadata(report, data);
  add_summary(report, data);
  if (data.comparison) add_error_table(report, *data.comparison);
  add_table_motion(report, data);
  for (const AnalysedBody& b : data.bodies) add_body(report, data, b);
  add_energy(report, data.results);
  return report;
}

}  // namespace freestand
