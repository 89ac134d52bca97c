#ifndef FREESTAND_POST_REPORT_BUILDER_H
#define FREESTAND_POST_REPORT_BUILDER_H

// The HTML report of a run (docs/report.md): metadata, table motion, each
// body's time histories, mode timeline, impacts, modal-interaction diagrams,
// impact decay, peaks, residuals, overturning and slip events, the energy
// ledger, and with a recording the overlays and the error table.

#include <optional>
#include <string>
#include <vector>

#include "html_report.h"
#include "recording.h"
#include "results.h"
#include "results_analysis.h"
#include "results_comparison.h"

namespace freestand {

struct ReportData {
  Results results;
  std::vector<AnalysedBody> bodies;          // the results, analysed
  std::optional<Recording> recording;
  std::optional<RunComparison> comparison;   // with a recording
};

// Reads and analyses the results and, when recording_path is not empty, reads
// the recording and compares it body by body. InputError naming the file at fault.
ReportData load_report_data(const std::string& results_path, const std::string& recording_path = "");

HtmlReport build_report(const ReportData& data);

}  // namespace freestand

#endif
