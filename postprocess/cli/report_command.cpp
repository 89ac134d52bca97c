// freestand report RESULTS.h5 [--recording REC]: the run as one
// self-contained HTML file (docs/freestand.md, docs/report.md).

#include <fmt/format.h>

#include <filesystem>

#include "commands.h"
#include "report_builder.h"

namespace freestand::cli {

namespace {

struct ReportOptions {
  std::string results;    // results.h5 of freestand run
  std::string recording;  // optional: NAME.csv (+ nominal) or NAME.h5
  std::string output;     // default: report.html next to the results
};

int report(const ReportOptions& o) {
  const ReportData data = load_report_data(o.results, o.recording);
  if (data.recording) print_warnings(*data.recording);
  const std::string output =
      o.output.empty() ? (std::filesystem::path(o.results).parent_path() / "report.html").string() : o.output;
  build_report(data).write(output);
  fmt::print("freestand report: {}\n", output);
  return 0;
}

}  // namespace

void add_report_command(CLI::App& app) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* sub = app.add_subcommand(
      "report",
      "Write the HTML report of a run: metadata, table motion, and per body the time histories of\n"
      "rock_x, rock_y, twist, slide_x, slide_y, uplift with impacts, the mode timeline, modal-interaction\n"
      "diagrams, impact decay against Housner's r, peaks, residuals, overturning and slip events; the energy\n"
      "ledger. With --recording: recorded overlays and the error table (peak error, residual difference,\n"
      "NRMSE, dominant frequencies, divergence time, time offset, gain). One self-contained file, no\n"
      "network needed to view or print it (docs/report.md).");
  sub->add_option("results", o->results, "results HDF5 of freestand run")->required()->check(CLI::ExistingFile);
  sub->add_option("--recording", o->recording,
                  "recording to overlay and compare: NAME.csv (with NAME.nominal.json) or NAME.h5; bodies by name");
  sub->add_option("-o,--output", o->output, "report file (default: report.html next to RESULTS.h5)");
  sub->callback([o] { guarded([&] { return report(*o); }); });
}

}  // namespace freestand::cli
