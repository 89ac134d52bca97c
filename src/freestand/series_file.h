#ifndef FREESTAND_SERIES_FILE_H
#define FREESTAND_SERIES_FILE_H

// An HDF5 file of equally long 1-D time series (e.g. /time,
// /bodies/tower/rock_x), appended one sample at a time and published
// atomically: data go to PATH.part, which is renamed to PATH only by
// commit(). A run that dies leaves PATH untouched (an older file of that
// name survives) and PATH.part as evidence.

#include <hdf5.h>

#include <string>
#include <vector>

namespace freestand {

class SeriesFile {
 public:
  explicit SeriesFile(std::string path);  // throws InputError if PATH.part cannot be created
  ~SeriesFile();
  SeriesFile(const SeriesFile&) = delete;
  SeriesFile& operator=(const SeriesFile&) = delete;

  // Declares a series (groups are created as needed); returns its column in
  // append() rows. Only before the first append().
  int add_series(const std::string& dataset_path, const std::string& units);
  // String attribute on a group or dataset that exists (or "/").
  void set_attribute(const std::string& object_path, const std::string& name,
                     const std::string& value);
  // One sample of every series, in add_series() order.
  void append(const std::vector<double>& row);
  // Writes what is buffered, closes the file and renames PATH.part to PATH.
  void commit();

  const std::string& path() const { return path_; }

 private:
  void flush();
  void ensure_group(const std::string& group_path);

  std::string path_;                         // final name
  std::string part_path_;                    // name while being written
  hid_t file_ = -1;                          // open HDF5 file, -1 once closed
  std::vector<hid_t> datasets_;              // one per series
  std::vector<std::vector<double>> buffer_;  // samples not yet written, per series
  hsize_t written_ = 0;                      // samples already in the file
};

}  // namespace freestand

#endif
