#include "freestand/series_file.h"

#include <fmt/format.h>

#include <cstdio>

#include "freestand/input_error.h"

namespace freestand {
namespace {

// Samples kept in memory before an HDF5 write: large enough that writes are
// rare (a 20 s record at 1 kHz is 20k samples), small enough to bound memory.
constexpr std::size_t kFlushSamples = 4096;
// Chunk length of the extendible datasets.
constexpr hsize_t kChunk = 4096;

}  // namespace

SeriesFile::SeriesFile(std::string path) : path_(std::move(path)), part_path_(path_ + ".part") {
  file_ = H5Fcreate(part_path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) throw InputError(fmt::format("{}: cannot create file", part_path_));
}

SeriesFile::~SeriesFile() {
  for (hid_t d : datasets_) H5Dclose(d);
  if (file_ >= 0) H5Fclose(file_);
}

void SeriesFile::ensure_group(const std::string& group_path) {
  // Create each missing level of /a/b/c in turn.
  for (std::size_t pos = group_path.find('/', 1);; pos = group_path.find('/', pos + 1)) {
    const std::string prefix = group_path.substr(0, pos);
    if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) {
      const hid_t g = H5Gcreate2(file_, prefix.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      if (g < 0) throw InputError(fmt::format("{}: cannot create group {}", part_path_, prefix));
      H5Gclose(g);
    }
    if (pos == std::string::npos) break;
  }
}

int SeriesFile::add_series(const std::string& dataset_path, const std::string& units) {
  if (written_ > 0 || (!buffer_.empty() && !buffer_[0].empty()))
    throw InputError(fmt::format("{}: series {} declared after data", part_path_, dataset_path));
  const std::size_t slash = dataset_path.rfind('/');
  if (slash != std::string::npos && slash > 0) ensure_group(dataset_path.substr(0, slash));
  const hsize_t initial = 0, unlimited = H5S_UNLIMITED;
  const hid_t space = H5Screate_simple(1, &initial, &unlimited);
  const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(props, 1, &kChunk);
  const hid_t dataset = H5Dcreate2(file_, dataset_path.c_str(), H5T_IEEE_F64LE, space,
                                   H5P_DEFAULT, props, H5P_DEFAULT);
  H5Pclose(props);
  H5Sclose(space);
  if (dataset < 0) throw InputError(fmt::format("{}: cannot create {}", part_path_, dataset_path));
  datasets_.push_back(dataset);
  buffer_.emplace_back();
  set_attribute(dataset_path, "units", units);
  return static_cast<int>(datasets_.size()) - 1;
}

void SeriesFile::set_attribute(const std::string& object_path, const std::string& name,
                               const std::string& value) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  H5Tset_strpad(type, H5T_STR_NULLTERM);
  const hid_t space = H5Screate(H5S_SCALAR);
  if (H5Aexists_by_name(file_, object_path.c_str(), name.c_str(), H5P_DEFAULT) > 0)
    H5Adelete_by_name(file_, object_path.c_str(), name.c_str(), H5P_DEFAULT);
  const hid_t attr = H5Acreate_by_name(file_, object_path.c_str(), name.c_str(), type, space,
                                       H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const herr_t status = attr < 0 ? -1 : H5Awrite(attr, type, value.c_str());
  if (attr >= 0) H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
  if (status < 0)
    throw InputError(fmt::format("{}: cannot write attribute {} of {}", part_path_, name, object_path));
}

void SeriesFile::append(const std::vector<double>& row) {
  if (row.size() != datasets_.size())
    throw InputError(fmt::format("{}: {} values for {} series", part_path_, row.size(),
                                 datasets_.size()));
  for (std::size_t i = 0; i < row.size(); ++i) buffer_[i].push_back(row[i]);
  if (buffer_[0].size() >= kFlushSamples) flush();
}

void SeriesFile::flush() {
  if (buffer_.empty() || buffer_[0].empty()) return;
  const hsize_t count = buffer_[0].size(), total = written_ + count;
  for (std::size_t i = 0; i < datasets_.size(); ++i) {
    H5Dset_extent(datasets_[i], &total);
    const hid_t file_space = H5Dget_space(datasets_[i]);
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, &written_, nullptr, &count, nullptr);
    const hid_t memory_space = H5Screate_simple(1, &count, nullptr);
    const herr_t status = H5Dwrite(datasets_[i], H5T_NATIVE_DOUBLE, memory_space, file_space,
                                   H5P_DEFAULT, buffer_[i].data());
    H5Sclose(memory_space);
    H5Sclose(file_space);
    if (status < 0) throw InputError(fmt::format("{}: write failed (disk full?)", part_path_));
    buffer_[i].clear();
  }
  written_ = total;
}

void SeriesFile::commit() {
  flush();
  for (hid_t d : datasets_) H5Dclose(d);
  datasets_.clear();
  const herr_t status = H5Fclose(file_);
  file_ = -1;
  if (status < 0) throw InputError(fmt::format("{}: closing failed", part_path_));
  if (std::rename(part_path_.c_str(), path_.c_str()) != 0)
    throw InputError(fmt::format("{}: cannot rename to {}", part_path_, path_));
}

}  // namespace freestand
