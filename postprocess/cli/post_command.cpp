// freestand post RESULTS.h5: channels CSV, ParaView series and a summary
// (docs/freestand.md).

#include "commands.h"
#include "post_pipeline.h"

namespace freestand::cli {

void add_post_command(CLI::App& app) {
  auto results = std::make_shared<std::string>();
  auto options = std::make_shared<PostOptions>();
  CLI::App* sub = app.add_subcommand(
      "post", "Postprocess a results file: the channels in the recording format (channels.csv and\n"
              "channels.nominal.json), the ParaView series (paraview/bodies.pvd, table.pvd), and a\n"
              "per-body summary. Everything is written next to RESULTS.h5.");
  sub->add_option("results", *results, "results HDF5 of freestand run")->required()->check(CLI::ExistingFile);
  sub->add_flag("!--no-csv", options->csv, "do not write channels.csv");
  sub->add_flag("!--no-vtk", options->vtk, "do not write the ParaView series");
  sub->add_option("--vtk-rate", options->vtk_rate, "ParaView frames per simulated second")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->callback([results, options] {
    guarded([&] {
      postprocess(*results, *options);
      return 0;
    });
  });
}

}  // namespace freestand::cli
