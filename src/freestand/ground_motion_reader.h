#ifndef FREESTAND_GROUND_MOTION_READER_H
#define FREESTAND_GROUND_MOTION_READER_H

// Reads recorded ground motion. Units are always stated by the user, never
// guessed: a wrong guess between g and m/s^2 is a factor of ten in the
// result, with nothing in the output to show it.

#include <string>
#include <vector>

namespace freestand {

// Where a ground-motion record is and how to read it.
struct RecordSource {
  std::string path;
  std::string format = "auto";  // "at2" (PEER, old and NGA headers), "columns"
                                // (whitespace text, first column time), "csv"
                                // (comma-separated with a header line); "auto":
                                // by extension .AT2/.at2 -> at2, .csv -> csv, else columns
  std::string column;           // columns: 1-based index of the value column
                                // (default "2"); csv: header name or 1-based
                                // index (default: the second column); at2: unused
  std::string units;            // "g", "m/s^2", "cm/s^2", "mm/s^2" (acceleration)
                                // or "m/s", "cm/s" (velocity); required
};

// A record in SI units: acceleration in m/s^2 or velocity in m/s.
struct GroundRecord {
  std::vector<double> t;      // s, strictly increasing, as in the file (may not start at 0)
  std::vector<double> value;  // SI value at t[i]
  bool is_velocity = false;   // true when units were a velocity
  std::string source;         // "path (column ...)", for messages
};

// Reads and validates the record. Throws InputError naming the file and line
// for: a missing file, a non-numeric token, NPTS or DT (AT2) that disagree
// with the data, non-increasing time, NaN/inf, an empty record, a missing
// column, an unknown unit.
GroundRecord read_ground_record(const RecordSource& source);

// Nodal accelerations of a velocity record (second-order differences: central
// inside, one-sided at the ends), for the piecewise-linear acceleration model.
std::vector<double> differentiate(const std::vector<double>& t, const std::vector<double>& v);

}  // namespace freestand

#endif
