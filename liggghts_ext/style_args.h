#ifndef FREESTAND_STYLE_ARGS_H
#define FREESTAND_STYLE_ARGS_H

// Reading input-script arguments in freestand's styles.

namespace LAMMPS_NS { class Error; }

namespace freestand {

// The finite number in `token`; otherwise stops the run with an error naming
// the style and the keyword, e.g. "fix rigid/convex: 'plane' expects a number, got 'x'".
double parse_number(LAMMPS_NS::Error *error, const char *style, const char *keyword,
                    const char *token);

}  // namespace freestand

#endif
