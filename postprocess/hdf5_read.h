#ifndef FREESTAND_POST_HDF5_READ_H
#define FREESTAND_POST_HDF5_READ_H

// Reading HDF5 files written by freestand or by others (h5py): every failure
// becomes an InputError naming the file and object, never HDF5's own error
// stack on the terminal.

#include <hdf5.h>

#include <optional>
#include <string>
#include <vector>

namespace freestand::hdf5 {

// Closes an HDF5 handle on scope exit.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() { if (id_ >= 0) close_(id_); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;                 // -1 when the open failed
  herr_t (*close_)(hid_t);   // H5Fclose, H5Gclose, ...
};

// Silences HDF5's error-stack printing while it lives.
class Quiet {
 public:
  Quiet();
  ~Quiet();
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;

 private:
  H5E_auto2_t function_ = nullptr;  // the handler to restore
  void* data_ = nullptr;
};

// Opens `path` read-only; InputError "path: ..." if missing, truncated or corrupt.
hid_t open_file(const std::string& path);

// A string attribute (fixed or variable length, ASCII or UTF-8), or nothing
// if absent. `where` names the object in messages.
std::optional<std::string> string_attribute(hid_t object, const char* name, const std::string& where);

// A 1-D numeric dataset as doubles, and its `units` attribute if present.
std::vector<double> read_dataset(hid_t group, const std::string& name, const std::string& where,
                                 std::optional<std::string>& units);

// Names of the links in a group, in name order.
std::vector<std::string> member_names(hid_t group, const std::string& where);

bool exists(hid_t file, const std::string& path);

}  // namespace freestand::hdf5

#endif
