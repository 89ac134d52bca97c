#ifndef FREESTAND_POST_DIAGNOSIS_REPORT_H
#define FREESTAND_POST_DIAGNOSIS_REPORT_H

// The HTML report of `freestand diagnose --report FILE.html` (docs/diagnose.md):
// the verdict, before/after overlays of the mismatched channels, the
// candidates of every round and the event features against both models.

#include <string>

#include "diagnosis.h"
#include "html_report.h"

namespace freestand::diagnosis {

// Adds the diagnosis sections to `report`.
void add_diagnosis_sections(HtmlReport& report, const Diagnosis& diagnosis);

}  // namespace freestand::diagnosis

#endif
