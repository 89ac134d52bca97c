#ifndef FREESTAND_TESTS_VALIDATION_SUPPORT_H
#define FREESTAND_TESTS_VALIDATION_SUPPORT_H

// Shared machinery of the validation tests (docs/validation.md): clump
// generation, running the inputs/validation scripts in-process, reading
// their fix print output, and the signal analysis (impacts and amplitudes of
// free rocking, threshold detection of uplift and slip).

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace freestand::validation {

// A fresh (emptied) directory validation/<name> below the working directory.
std::filesystem::path fresh_dir(const std::string& name);

// A rectangular block built as a stock multisphere clump by
// inputs/free_rocking/gen_block_clump.py: base spheres of radius rbase
// centred on the base corners (the only spheres that touch the floor while
// the block tilts less than 60 degrees), envelope spheres of radius rside.
struct BlockClump {
  double width;        // 2b, along x (m)
  double depth;        // 2d, along y (m)
  double height;       // 2h, along z (m)
  double mass;         // kg (uniform box inertia)
  int nz = 8;          // vertical-edge subdivisions
  int ntop = 1;        // extra spheres per top edge
  double rbase = 0.001;
  double rside = 0.025;
};

// Writes <dir>/<name>.clump and <dir>/<name>.in; returns the path prefix
// <dir>/<name> that the input scripts take as `clump`.
std::string make_clump(const std::filesystem::path& dir, const std::string& name,
                       const BlockClump& block);

// Opening of an input script for freestand's convex bodies: atom_style sphere
// with an atom map (no sorting), fixed boundaries, ranks split along x,
// newton off (pair convex needs it), velocities communicated, SI units, one
// atom type, the box [-half_x, half_x] x [-half_y, half_y] x [z_lo, z_hi].
std::string convex_preamble(double half_x, double half_y, double z_lo, double z_hi);

// Absolute path of a file under the source tree.
std::string source_path(const std::string& relative);

// Runs an input script in-process with freestand's styles (one LIGGGHTS
// instance at a time), after defining the given index variables, which take
// precedence over the script's own defaults.
using Variables = std::vector<std::pair<std::string, std::string>>;
void run_input(const std::string& script, const Variables& variables);

// The numeric rows of a fix print file (comment lines skipped); every row
// must have at least `columns` values.
std::vector<std::vector<double>> read_rows(const std::filesystem::path& file, std::size_t columns);

// One column of those rows.
std::vector<double> column(const std::vector<std::vector<double>>& rows, std::size_t index);

// x with 17 significant digits, for input-script variables.
std::string num(double x);

// Wall-clock seconds since an arbitrary origin.
double wall_seconds();

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

}  // namespace freestand::validation

#endif
