// freestand tosses: the DAIR Lab cube tosses as recordings (docs/recordings.md).

#include <fmt/format.h>

#include "commands.h"
#include "cube_toss.h"

namespace freestand::cli {

namespace {

struct TossesOptions {
  std::string data;       // cube_tosses_0-299.csv.gz
  std::string directory;  // where cube_toss_NNN.{csv,nominal.json} go
  int first = 0, last = 299;
};

int convert(const TossesOptions& o) {
  if (o.first > o.last) throw std::invalid_argument(fmt::format("--first {} is after --last {}", o.first, o.last));
  const std::vector<std::string> stems = convert_cube_tosses(o.data, o.directory, o.first, o.last);
  fmt::print("freestand tosses: {} tosses ({}..{}) -> {}/cube_toss_NNN.{{csv,nominal.json}}\n", stems.size(),
             o.first, o.last, o.directory);
  return 0;
}

}  // namespace

void add_tosses_command(CLI::App& app) {
  auto options = std::make_shared<TossesOptions>();
  CLI::App* sub = app.add_subcommand(
      "tosses", "Convert the DAIR Lab cube tosses (gzipped CSV) into recordings, one per toss, whose\n"
                "nominal.json is a scenario: `freestand run cube_toss_007.nominal.json` simulates the toss.");
  sub->add_option("data", options->data, "cube_tosses_0-299.csv.gz (../shared/data/experiments/cube_toss/)")
      ->required()
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", options->directory, "output directory (created)")->required();
  sub->add_option("--first", options->first, "first toss id")->capture_default_str();
  sub->add_option("--last", options->last, "last toss id")->capture_default_str();
  sub->callback([options] { guarded([&] { return convert(*options); }); });
}

}  // namespace freestand::cli
