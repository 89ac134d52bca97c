#ifndef FREESTAND_POST_SHOOTING_H
#define FREESTAND_POST_SHOOTING_H

// Multiple shooting (docs/diagnose.md, "Multiple shooting"): a recording of
// one body on the table cut where the body rests before a motion episode.
// Each piece starts from the state measured there (at rest: the pose from the
// slide and twist channels, no velocity), so a model error in one episode does
// not carry into the next: rocking is chaotic, and a whole-record comparison
// compounds every early difference.

#include <vector>

#include "recording.h"

namespace freestand {

struct ShootingOptions {
  double min_rest = 0.3;      // s: a rest this long before a motion episode is a cut
  double margin = 0.1;        // s: the cut is this long before the motion starts (still at rest)
  double min_segment = 0.5;   // s: no piece shorter than this (too few events to compare)
  double max_tilt_sds = 5;    // a rest tilted by more angle-noise s.d. than this is no cut (not on its base)
};

// The pieces of `recording`, in time order, each a recording of its own: its
// samples (times unchanged), the body's slide, twist and uplift channels minus
// their value at the cut (recordings state them from the start), and its
// nominal with the body at the measured rest pose (position moved by the slide,
// turned by the twist about the vertical, no velocity or spin). Path:
// "PATH@T s". The recording itself when it has several bodies (a stacked
// body's state is not a pose on the table) or no cut.
std::vector<Recording> shooting_segments(const Recording& recording, const ShootingOptions& options = {});

}  // namespace freestand

#endif
