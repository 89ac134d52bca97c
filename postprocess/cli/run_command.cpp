// freestand run SCENARIO.json: writes the LIGGGHTS input script and scene
// into a run directory, runs freestand-lmp with a progress bar, then
// postprocesses the results (docs/freestand.md).

#include <fmt/format.h>

#include <filesystem>

#include "atomic_file.h"
#include "commands.h"
#include "liggghts_runner.h"
#include "post_pipeline.h"
#include "progress.h"
#include "scenario.h"

namespace freestand::cli {

namespace fs = std::filesystem;

namespace {

struct RunOptions {
  std::string scenario;                // SCENARIO.json
  std::string directory;               // run directory; default: the scenario's stem in the working directory
  std::vector<std::string> overrides;  // --var key=value
  int processes = 0;                   // --np; 0: the scenario's simulation.processes
  bool post = true;                    // postprocess after the run
  bool dry_run = false;                // write the files, do not run
};

int run(const RunOptions& o) {
  const Scenario scenario = read_scenario(o.scenario, o.overrides);
  const RunFiles files;
  GeneratedRun generated = generate_run(scenario, files);
  if (o.processes > 0) generated.settings.processes = o.processes;
  const fs::path dir = o.directory.empty() ? fs::path(o.scenario).stem() : fs::path(o.directory);
  fs::create_directories(dir);
  write_file_atomically((dir / files.scenario).string(), scenario.document.dump(2) + "\n");
  write_file_atomically((dir / files.scene).string(), generated.scene.dump(2) + "\n");
  write_file_atomically((dir / files.script).string(), generated.script);
  fmt::print("freestand run: {} -> {}/ ({} simulated s, {} rank{})\n", o.scenario, dir.string(),
             generated.settings.duration, generated.settings.processes,
             generated.settings.processes > 1 ? "s" : "");
  std::fflush(stdout);  // before the progress bar and any error on stderr
  if (o.dry_run) {
    fmt::print("  input script {} written; run it with: cd {} && freestand-lmp -in {}\n",
               (dir / files.script).string(), dir.string(), files.script);
    return 0;
  }
  ProgressBar bar("  simulating");
  const LiggghtsOutcome outcome = run_liggghts(
      {default_liggghts_executable(), dir.string(), files.script, "log.liggghts", generated.settings.processes},
      [&](long step, long total) { bar.update(step, total); });
  bar.finish();
  if (outcome.status != 0) {
    std::fprintf(stderr, "freestand run: the simulation failed:\n%s", outcome.error.c_str());
    std::fprintf(stderr, "  log: %s; results left as they were\n", (dir / "log.liggghts").string().c_str());
    return 1;
  }
  const std::string results = (dir / files.results).string();
  fmt::print("  results: {}\n", results);
  if (o.post) postprocess(results, PostOptions{});
  return 0;
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* sub = app.add_subcommand(
      "run", "Simulate a scenario (docs/scenario.md): write the LIGGGHTS input script and scene into a run\n"
             "directory, run freestand-lmp with progress and ETA, then postprocess (results.h5, ParaView\n"
             "series, channels CSV, summary). The script can be edited and rerun with freestand-lmp.");
  sub->add_option("scenario", options->scenario, "scenario JSON (a recording's nominal.json plus table_motion works)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", options->directory, "run directory (default: the scenario's name, here)");
  sub->add_option("--var", options->overrides,
                  "override a scenario value: key=value, e.g. simulation.duration=10, interfaces.0.mu=0.5,\n"
                  "bodies.tower.mass=900, table_motion.x.pga=\"0.3 g\" (repeatable)");
  sub->add_option("--np", options->processes, "MPI ranks (default: simulation.processes, or 1)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("!--no-post", options->post, "skip postprocessing");
  sub->add_flag("--dry-run", options->dry_run, "write the run directory's files only");
  sub->callback([options] { guarded([&] { return run(*options); }); });
}

}  // namespace freestand::cli
