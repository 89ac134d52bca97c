#ifndef FREESTAND_POST_DIAGNOSIS_VERDICT_H
#define FREESTAND_POST_DIAGNOSIS_VERDICT_H

// The plain words of `freestand diagnose` (docs/diagnose.md, "The verdict"): the verdict
// text from a finished Diagnosis, and a value with its unit. diagnosis_json (diagnosis.h) is
// defined with them.

#include <string>

#include "diagnosis.h"

namespace freestand::diagnosis {

// A candidate's value with 3 significant digits and its unit.
std::string format_value(const Candidate& c, double v);
// " (friction_decay 5 s/m)": a candidate's second parameter (its shape), or "" when it has none.
std::string format_shape(const Candidate& c);

// The verdict: measurement and numerics first, then where the model as given mismatched, each
// accepted effect, and where the search ended (within the noise, or what is unexplained).
std::string verdict_text(const Diagnosis& d);

}  // namespace freestand::diagnosis

#endif
