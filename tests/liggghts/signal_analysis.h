#ifndef FREESTAND_TESTS_SIGNAL_ANALYSIS_H
#define FREESTAND_TESTS_SIGNAL_ANALYSIS_H

// Signal analysis of simulation output, free of LIGGGHTS so that the
// benchmarks (bench/housner_error.cpp) analyse their runs with the same code
// as the validation tests: reading fix print columns, impacts and amplitudes
// of free rocking and their errors against Housner, threshold detection.

#include <filesystem>
#include <vector>

#include "../reference/housner.h"

namespace freestand::validation {

// The numeric rows of a fix print file (comment lines skipped); every row
// must have at least `columns` values.
std::vector<std::vector<double>> read_rows(const std::filesystem::path& file, std::size_t columns);

// One column of those rows.
std::vector<double> column(const std::vector<std::vector<double>>& rows, std::size_t index);

// Free rocking, as Housner describes it: impacts are the zero crossings of
// the rocking angle, amplitude n is the largest |theta| between impacts n
// and n+1 (refined by a parabola through the largest sample and its
// neighbours). A crossing counts only once |theta| then exceeds
// `hysteresis` with the new sign, so contact chatter near theta = 0 cannot
// split a half-cycle.
struct RockingCycles {
  std::vector<double> impacts;     // s
  std::vector<double> amplitudes;  // rad, amplitudes[n] between impacts[n] and impacts[n+1]
};
RockingCycles rocking_cycles(const std::vector<double>& t, const std::vector<double>& theta,
                             double hysteresis);

// First sample k >= first at which the finite-difference rate of `value` over
// `window` samples, (value[k] - value[k - window]) / (t[k] - t[k - window]),
// times `direction` (+1 or -1) exceeds `threshold`; -1 if none.
long first_rate_above(const std::vector<double>& t, const std::vector<double>& value,
                      std::size_t window, double direction, double threshold, std::size_t first);

// Linear interpolation of (x, y) at xi (x increasing; clamped at the ends).
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xi);

// A free-rocking record (released at rest from |theta.front()|) against
// Housner's exact amplitude map and nonlinear half-cycle durations
// (../shared/data/benchmarks.md 1.3-1.5): relative errors, signed.
struct HousnerErrors {
  std::vector<double> amplitude;   // theta_n / Housner's theta_n - 1, n = 1..count (fewer if the
                                   // record has fewer half-cycles)
  std::vector<double> half_cycle;  // (impact n+1 - impact n) / Housner's - 1, n = 1..count
  double first_impact = 0.0;       // time of the first impact / Housner's quarter period - 1
  RockingCycles cycles;            // all impacts and amplitudes found (hysteresis as rocking_cycles)
};
HousnerErrors housner_errors(const std::vector<double>& t, const std::vector<double>& theta,
                             const reference::HousnerBlock& block, std::size_t count,
                             double hysteresis);

}  // namespace freestand::validation

#endif
