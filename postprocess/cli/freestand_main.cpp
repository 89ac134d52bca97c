// freestand: run scenarios, postprocess results, compare with recordings,
// report, calibrate (docs/freestand.md).

#include <fmt/format.h>

#include <cstdio>

#include "commands.h"

namespace freestand::cli {

void guarded(const std::function<int()>& body) {
  int status = 1;
  try {
    status = body();
  } catch (const std::exception& e) {  // InputError names the file, line or field
    std::fprintf(stderr, "freestand: error: %s\n", e.what());
  }
  if (status != 0) throw CLI::RuntimeError(status);
}

void print_warnings(const Recording& recording) {
  for (const std::string& w : recording.warnings) std::fprintf(stderr, "freestand: warning: %s\n", w.c_str());
}

}  // namespace freestand::cli

int main(int argc, char** argv) {
  CLI::App app{"freestand " FREESTAND_VERSION
               ": freestanding bodies (statues, equipment, column drums) on shake tables.\n"
               "Run a scenario, postprocess its results, compare with recordings, report, calibrate.\n"
               "Documentation: docs/freestand.md"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "freestand " FREESTAND_VERSION);
  freestand::cli::add_run_command(app);
  freestand::cli::add_post_command(app);
  freestand::cli::add_calibrate_command(app);
  freestand::cli::add_tosses_command(app);
  freestand::cli::add_report_command(app);
  freestand::cli::add_compare_command(app);
  freestand::cli::add_diagnose_command(app);
  freestand::cli::add_generate_command(app);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
