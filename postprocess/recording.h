#ifndef FREESTAND_POST_RECORDING_H
#define FREESTAND_POST_RECORDING_H

// Recordings in the format of ../shared/recording-format.md: NAME.csv plus
// NAME.nominal.json, or one HDF5 file with /channels/<column> datasets and
// the nominal JSON text in the attribute /nominal. docs/recordings.md says
// what is read, what is derived and which extension columns are accepted.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace freestand {

// One column of a recording, other than time. Lost samples are NaN.
struct RecordingChannel {
  std::string name;            // column name: "table_ax", "tower.rock_x", "cube.qw", ...
  std::vector<double> values;  // one per time sample, SI units
  bool derived = false;        // computed from other table channels, not in the file
};

struct Recording {
  std::string path;                       // file it was read from (empty when built in memory)
  nlohmann::json nominal;                 // the sidecar as written
  std::vector<double> time;               // s, strictly increasing
  std::vector<RecordingChannel> channels; // file order (HDF5: by name), then derived ones
  std::vector<std::string> warnings;      // unknown fields and columns, each reported once

  // Body names in sidecar order.
  std::vector<std::string> body_names() const;
  // The column called `name`, or null.
  const RecordingChannel* find(const std::string& name) const;
  // The column `body.channel`; throws InputError naming the recording when absent.
  const std::vector<double>& body_channel(const std::string& body, const std::string& channel) const;
  // Table channel of kind 'a', 'v' or 'd' along axis 'x', 'y' or 'z' (measured
  // or derived), or null when the table does not move along that axis.
  const std::vector<double>* table_channel(char kind, char axis) const;
};

// The longest run of lost table acceleration a replay bridges, linearly (s): a straight line over
// 0.05 s misses a 2 Hz sine, a typical strong-motion frequency, by at most 5 % of its amplitude
// ((pi f T)^2 / 2).
inline constexpr double kLongestTableBridge = 0.05;

// The table's acceleration along `axis` as a simulation replays it: lost samples bridged
// (signal::bridge_lost). Throws InputError naming the recording and the time when a run of lost
// samples spans more than kLongestTableBridge. Null channel: an empty vector.
std::vector<double> replayed_table_acceleration(const Recording& recording, char axis);

// Its samples at times up to `end` (all channels cut alike).
Recording up_to(const Recording& recording, double end);

// Reads NAME.csv (+ NAME.nominal.json next to it), NAME.h5 / NAME.hdf5, or
// a stem NAME for which one of those exists. Missing table channels of an
// axis are derived from the present ones. Throws InputError naming file and
// line/column for malformed input.
Recording read_recording(const std::string& path);

// Writes STEM.csv and STEM.nominal.json (each to a temporary name, then
// renamed), or with hdf5 = true STEM.h5. Derived channels are not written:
// reading the files back derives them again. Lost samples are written as nan.
// Throws InputError when the recording is inconsistent or a file cannot be
// written.
void write_recording(const std::string& path_stem, const Recording& recording, bool hdf5 = false);

}  // namespace freestand

#endif
