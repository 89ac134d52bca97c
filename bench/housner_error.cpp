// Errors of free-rocking records (time, rock_x columns; '#' comments skipped)
// against Housner's exact amplitude map and half-cycle durations, with the
// analysis of the validation tests (tests/liggghts/signal_analysis.h), so
// that bench/time_to_accuracy.sh judges freestand and MuJoCo alike.
// Prints one line per file, in percent: the largest |error| of theta_1..5,
// theta_1..5 errors, the largest |error| of half-cycles 1..5, the first impact
// time error. A record with fewer than 5 half-cycles prints nan for the rest.

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "../tests/liggghts/signal_analysis.h"

namespace {

namespace fv = freestand::validation;

constexpr std::size_t kHalfCycles = 5;

double largest_magnitude(const std::vector<double>& errors) {
  if (errors.size() < kHalfCycles) return std::numeric_limits<double>::quiet_NaN();
  double worst = 0.0;
  for (double e : errors) worst = std::max(worst, std::fabs(e));
  return worst;
}

std::string row(const std::string& file, const freestand::reference::HousnerBlock& block) {
  const auto rows = fv::read_rows(file, 2);
  if (rows.size() < 3) throw std::runtime_error(file + ": fewer than 3 samples");
  // Hysteresis 2 % of alpha, as tests/liggghts/test_convex_rocking.cpp: far
  // above contact chatter, far below the smallest amplitude (16 % of alpha).
  const fv::HousnerErrors e = fv::housner_errors(fv::column(rows, 0), fv::column(rows, 1), block,
                                                 kHalfCycles, 0.02 * block.alpha());
  std::string out = fmt::format("{:.3f}", 100 * largest_magnitude(e.amplitude));
  for (std::size_t n = 0; n < kHalfCycles; ++n)
    out += n < e.amplitude.size() ? fmt::format(" {:+.3f}", 100 * e.amplitude[n]) : " nan";
  out += fmt::format(" {:.3f}", 100 * largest_magnitude(e.half_cycle));
  return out + (e.cycles.impacts.empty() ? " nan" : fmt::format(" {:+.3f}", 100 * e.first_impact));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Free-rocking records against Housner (percent errors, one line per file)"};
  freestand::reference::HousnerBlock block{0.125, 0.5};
  std::vector<std::string> files;
  app.add_option("--half-width", block.half_width, "b: half the base width along x (m)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--half-height", block.half_height, "h: half the height (m)")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("files", files, "records: time and rock_x columns")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    for (const auto& file : files) fmt::print("{}\n", row(file, block));
  } catch (const std::exception& error) {
    fmt::print(stderr, "housner_error: {}\n", error.what());
    return 1;
  }
  return 0;
}
