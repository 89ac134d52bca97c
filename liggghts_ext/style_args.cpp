#include "style_args.h"

#include <cmath>
#include <cstdlib>
#include <string>

#include "error.h"

namespace freestand {

double parse_number(LAMMPS_NS::Error *error, const char *style, const char *keyword,
                    const char *token) {
  char *end = nullptr;
  const double value = std::strtod(token, &end);
  if (end == token || *end != '\0' || !std::isfinite(value))
    error->all(FLERR, (std::string(style) + ": '" + keyword + "' expects a number, got '" + token +
                       "'").c_str());
  return value;
}

}  // namespace freestand
