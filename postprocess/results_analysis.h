#ifndef FREESTAND_POST_RESULTS_ANALYSIS_H
#define FREESTAND_POST_RESULTS_ANALYSIS_H

// The bridge from a results file (and its scenario) or a recording (and its
// nominal) to the motion analysis: each body's channels, exact rates where
// the state is known, the support's uplift, and the base geometry it rocks on.

#include <string>
#include <vector>

#include "motion_analysis.h"
#include "recording.h"
#include "results.h"

namespace freestand {

struct AnalysedBody {
  std::string name;
  std::string supported_by;           // "table" or the body below
  analysis::BodyMotion motion;
  analysis::BodyGeometry geometry;
  analysis::MotionSummary summary;
};

// Every body of a results file, analysed (exact rates from the stored
// velocities; geometry from the scenario).
std::vector<AnalysedBody> analyse_results(const Results& results,
                                          const analysis::AnalysisParameters& parameters = {});

// Every body of a recording, analysed (rates fitted; geometry from the
// nominal; noise from its sensor_noise when stated).
std::vector<AnalysedBody> analyse_recording(const Recording& recording);

// The analysis parameters for a recording's nominal (sensor_noise.angle and
// .length when stated, else the defaults).
analysis::AnalysisParameters parameters_for(const nlohmann::json& nominal);

}  // namespace freestand

#endif
