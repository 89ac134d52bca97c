#ifndef FREESTAND_TESTS_VALIDATION_SUPPORT_H
#define FREESTAND_TESTS_VALIDATION_SUPPORT_H

// Shared machinery of the validation tests (docs/validation.md): clump
// generation and running the inputs/validation scripts in-process; the
// analysis of their fix print output is in signal_analysis.h.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "signal_analysis.h"

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


// x with 17 significant digits, for input-script variables.
std::string num(double x);

// Wall-clock seconds since an arbitrary origin.
double wall_seconds();


}  // namespace freestand::validation

#endif
