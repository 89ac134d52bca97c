#ifndef FREESTAND_POST_EVENTS_FILE_H
#define FREESTAND_POST_EVENTS_FILE_H

// Writes what `freestand post` found in each body's motion into the results
// file, under /events/<body>/ (docs/results-format.md), replacing earlier
// events. The file is rewritten as a copy and renamed over the original, so
// an interrupted write leaves the results as they were.

#include <string>
#include <vector>

#include "results_analysis.h"

namespace freestand {

void write_events(const std::string& results_path, const std::vector<AnalysedBody>& bodies);

}  // namespace freestand

#endif
