#ifndef FREESTAND_POST_RESULTS_H
#define FREESTAND_POST_RESULTS_H

// A results file of `freestand run` (docs/results-format.md), read whole:
// time, table motion, every body's state and channels, the energy ledger,
// the scenario that was run, and the events `freestand post` added.

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "recording.h"

namespace freestand {

using Series = std::vector<double>;

struct BodyResults {
  std::string name;
  std::map<std::string, Series> series;  // rock_x ... uplift, x y z, qw qx qy qz, vx vy vz, wx wy wz
  // The series `key`; InputError naming the body and key when absent.
  const Series& at(const std::string& key) const;
  bool has(const std::string& key) const { return series.count(key) > 0; }
};

struct Results {
  std::string path;
  std::map<std::string, std::string> attributes;  // root attributes: creator, versions, time_step, ...
  nlohmann::json scenario;                         // the scenario as run, or null
  Series time;                                     // s
  std::map<std::string, Series> table;             // ax ay az vx vy vz dx dy dz; empty: fixed table
  std::vector<BodyResults> bodies;                 // in file (name) order
  std::map<std::string, Series> energy;            // the ledger (J); empty if not written

  const BodyResults& body(const std::string& name) const;
  double time_step() const;  // from the time_step attribute (s), 0 if absent
};

// Reads a results file; InputError naming the file and dataset for a missing
// /time, a series of another length, a truncated or foreign file.
Results read_results(const std::string& path);

// The channels (and table motion and pose columns) as a recording, with the
// scenario's bodies and interfaces as its nominal, so results export to the
// recording format (docs/recordings.md) and compare like recordings.
Recording results_as_recording(const Results& results);

}  // namespace freestand

#endif
