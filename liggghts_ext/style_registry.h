#ifndef FREESTAND_STYLE_REGISTRY_H
#define FREESTAND_STYLE_REGISTRY_H

#include <cstdio>
#include <string>
#include <vector>

namespace LAMMPS_NS { class LAMMPS; }

namespace freestand {

// Names of the styles freestand adds, by kind ("fix", "compute", "pair").
struct StyleName {
  std::string kind;  // "fix", "compute" or "pair"
  std::string name;  // the name used in input scripts, e.g. "shaketable"
};

// Adds every freestand style to the style maps of a LAMMPS instance, so the
// input script can name them exactly like stock styles. Call once, right
// after the instance is constructed and before any input is read.
void register_freestand_styles(LAMMPS_NS::LAMMPS* lmp);

// The styles register_freestand_styles() adds.
std::vector<StyleName> freestand_styles();

// Prints the command-line options and every registered command, fix,
// compute and pair style (stock and freestand's, ours marked), as
// `liggghts -h` does for the stock binary.
void print_style_help(LAMMPS_NS::LAMMPS* lmp, std::FILE* out);

}  // namespace freestand

#endif
