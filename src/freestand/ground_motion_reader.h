#ifndef FREESTAND_GROUND_MOTION_READER_H
#define FREESTAND_GROUND_MOTION_READER_H

// Reads recorded ground motion. Units are always stated by the user, never
// guessed: a wrong guess between g and m/s^2 is a factor of ten in the
// result, with nothing in the output to show it.

#include <string>
#include <vector>

namespace freestand {

// Where a ground-motion record is and how to read it (docs/ground-motion.md).
struct RecordSource {
  std::string path;
  std::string format = "auto";  // "at2" (PEER, old and NGA headers), "columns"
                                // (whitespace text, first column time), "csv"
                                // (comma-separated with a header line); "auto":
                                // by extension .AT2/.at2 -> at2, .csv -> csv, else columns
  std::string column;           // columns: 1-based index of the value column
                                // (default "2"); csv: header name or 1-based
                                // index (default: the second column); at2: must be empty
  std::string units;            // "g" (9.80665 m/s^2), "m/s^2", "cm/s^2", "mm/s^2"
                                // (acceleration) or "m/s", "cm/s" (velocity); required
};

// A record in SI units: acceleration in m/s^2 or velocity in m/s.
struct GroundRecord {
  std::vector<double> t;      // s, strictly increasing, as in the file (may not start at 0)
  std::vector<double> value;  // SI value at t[i]
  bool is_velocity = false;   // true when units were a velocity
  std::string source;         // "path (column ...)", for messages
};

// Reads and validates the record. Formats:
//   at2      4 header lines; units stated on line 3 ("... IN UNITS OF G") must
//            match the units given; line 4 holds NPTS and DT ("NPTS= 5590, DT= .01000 SEC", any
//            spacing, or "5590 .01 NPTS, DT"); then NPTS values, any number per
//            line; t_i = i DT.
//   columns  whitespace-separated numbers, every data line with the same
//            column count; leading lines without any number are a header.
//   csv      a header line of column names, then comma-separated numbers.
// Blank lines, and in columns/csv lines starting with '#', are skipped.
// Throws InputError "path:line: what" for: a non-numeric token, NPTS or DT
// (AT2) that disagree with the data or are invalid, non-increasing time,
// NaN/inf, a missing column, a ragged line; "path: what" where no line is at
// fault: a missing file, an unknown unit, an empty record.
GroundRecord read_ground_record(const RecordSource& source);

// Nodal accelerations of a velocity record (second-order differences: central
// inside, one-sided at the ends, exact for quadratic v also on uneven steps),
// for the piecewise-linear acceleration model. Integrating them back does not
// return v exactly (an O(h^2) difference). Throws InputError for < 3 samples.
std::vector<double> differentiate(const std::vector<double>& t, const std::vector<double>& v);

}  // namespace freestand

#endif
