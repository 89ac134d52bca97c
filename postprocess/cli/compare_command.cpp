// freestand compare RESULTS.h5 RECORDING: simulation against recording,
// body by body, with the error table on the terminal, optionally as JSON
// and as the HTML report with overlays (docs/freestand.md).

#include <fmt/format.h>

#include <cmath>

#include "atomic_file.h"
#include "commands.h"
#include "freestand/body_channels.h"
#include "report_builder.h"

namespace freestand::cli {

namespace {

struct CompareOptions {
  std::string results, recording;
  std::string json;    // every metric, SI units
  std::string report;  // HTML with overlays
};

// One line per compared channel, the channel that diverges first starred.
void print_errors(const RunComparison& run) {
  fmt::print("  {:<16} {:<8} {:>7}", "body", "channel", "samples");
  for (const Metric& m : error_metrics()) fmt::print(" {:>14}", m.heading);
  fmt::print("\n  {:<16} {:<8} {:>7}", "", "", "");
  for (const Metric& m : error_metrics()) fmt::print(" {:>14}", m.in_channel_units ? "(rad, mm)" : *m.unit ? fmt::format("({})", m.unit) : "");
  fmt::print("\n");
  for (const ComparedBody& b : run.bodies) {
    const int first = first_divergence(b.comparison);
    for (int c = 0; c < analysis::kChannelCount; ++c) {
      const comparison::ChannelComparison& cc = b.comparison.channels[c];
      if (cc.samples == 0 || !channel_moved(b, c, run.parameters)) continue;
      fmt::print("  {:<16} {:<8} {:>7}", b.simulated.name, channel_names()[c], cc.samples);
      for (const Metric& m : error_metrics()) {
        const double scale = m.in_channel_units && c >= analysis::kSlideX ? 1e3 : 1.0;  // lengths in mm
        const bool star = c == first && std::string(m.key) == "divergence_time";
        fmt::print(" {:>13.4g}{}", m.value(cc) * scale, star ? "*" : " ");
      }
      fmt::print("\n");
    }
  }
  fmt::print("  * first divergence of the body; nan: not defined (no divergence, no spectrum peak); channels that stay\n"
             "    within the analysis' resolution in both are left out (the JSON has them)\n");
}

int compare(const CompareOptions& o) {
  const ReportData data = load_report_data(o.results, o.recording);
  if (data.recording) print_warnings(*data.recording);
  const RunComparison& run = *data.comparison;
  std::vector<std::string> names;
  for (const ComparedBody& b : run.bodies) names.push_back(b.simulated.name);
  fmt::print("freestand compare: {} against {}\n  compared: {}\n", o.results, o.recording,
             names.empty() ? "no body" : fmt::format("{}", fmt::join(names, ", ")));
  if (!run.unrecorded.empty())
    fmt::print("  not in the recording (not compared): {}\n", fmt::join(run.unrecorded, ", "));
  print_errors(run);
  if (!o.json.empty()) {
    nlohmann::json out = comparison_json(run);
    out["results"] = o.results, out["recording"] = o.recording;
    write_file_atomically(o.json, out.dump(2) + "\n");
    fmt::print("  metrics (JSON): {}\n", o.json);
  }
  if (!o.report.empty()) {
    build_report(data).write(o.report);
    fmt::print("  report: {}\n", o.report);
  }
  return 0;
}

}  // namespace

void add_compare_command(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* sub = app.add_subcommand(
      "compare",
      "Compare a simulation with a recording, body by body (matched by name; a recorded body the results\n"
      "lack is an error, simulated bodies the recording lacks are listed and skipped). Prints per channel\n"
      "the peak error, residual difference, NRMSE, dominant frequencies, divergence time, time offset and\n"
      "gain (definitions: docs/postprocessing.md); --json writes every metric, --report the HTML report\n"
      "with the recording overlaid.");
  sub->add_option("results", o->results, "results HDF5 of freestand run")->required()->check(CLI::ExistingFile);
  sub->add_option("recording", o->recording, "recording: NAME.csv (with NAME.nominal.json) or NAME.h5")->required();
  sub->add_option("--json", o->json, "write every metric as JSON (SI units)");
  sub->add_option("--report", o->report, "write the HTML report with the recording overlaid");
  sub->callback([o] { guarded([&] { return compare(*o); }); });
}

}  // namespace freestand::cli
