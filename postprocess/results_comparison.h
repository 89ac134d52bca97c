#ifndef FREESTAND_POST_RESULTS_COMPARISON_H
#define FREESTAND_POST_RESULTS_COMPARISON_H

// A results file against a recording, body by body (matched by name): both
// analysed, every channel compared (comparison.h), and the metrics named once
// for the terminal table, the JSON and the HTML report (docs/freestand.md).

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "comparison.h"
#include "recording.h"
#include "results_analysis.h"

namespace freestand {

struct ComparedBody {
  AnalysedBody simulated, recorded;
  comparison::BodyComparison comparison;
};

struct RunComparison {
  std::vector<ComparedBody> bodies;       // the recorded bodies, in the results' order
  std::vector<std::string> unrecorded;    // bodies of the results the recording lacks
  analysis::AnalysisParameters parameters;  // the recording's noise (nominal sensor_noise)
};

// Throws InputError naming the recording and the body when the recording has
// a body the results do not (listing the results' bodies).
RunComparison compare_run(const std::vector<AnalysedBody>& simulated, const Recording& recording,
                          const std::string& results_path);

// One column of the error table: a metric of a channel comparison.
struct Metric {
  const char* key;      // JSON key
  const char* heading;  // table heading
  bool in_channel_units;  // carries the channel's unit (else: its own, in `unit`)
  const char* unit;     // "%", "s", "Hz", "" (dimensionless)
  double (*value)(const comparison::ChannelComparison&);
};
// Peak error, residual difference, NRMSE, dominant frequency (simulated,
// recorded), divergence time, time offset, gain, correlation.
const std::vector<Metric>& error_metrics();

// A channel moved when its peak exceeds what the analysis resolves
// (threshold_sigmas x the noise of its kind); an unmeasured channel did not.
bool channel_moved(const AnalysedBody& body, int channel, const analysis::AnalysisParameters& parameters);
// In the simulation or the recording.
bool channel_moved(const ComparedBody& body, int channel, const analysis::AnalysisParameters& parameters);

// The channel of a body that diverges first (smallest divergence time), or -1.
int first_divergence(const comparison::BodyComparison& comparison);

// Every metric of every compared channel, impact decay, and what was not compared.
nlohmann::json comparison_json(const RunComparison& run);

}  // namespace freestand

#endif
