#include "hdf5_read.h"

#include <fmt/format.h>

#include <fstream>

#include "freestand/input_error.h"

namespace freestand::hdf5 {

namespace {

}  // namespace

Quiet::Quiet() {
  H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

Quiet::~Quiet() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

hid_t open_file(const std::string& path) {
  if (!std::ifstream(path).good()) fail(path, "cannot open file");
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) fail(path, "not a readable HDF5 file (truncated or corrupt)");
  return file;
}

std::optional<std::string> string_attribute(hid_t object, const char* name, const std::string& where) {
  if (H5Aexists(object, name) <= 0) return std::nullopt;
  const Handle attr(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
  const Handle type(attr.valid() ? H5Aget_type(attr.get()) : -1, H5Tclose);
  if (!type.valid() || H5Tget_class(type.get()) != H5T_STRING)
    fail(where, fmt::format("attribute '{}' must be a string", name));
  if (H5Tis_variable_str(type.get()) > 0) {
    const Handle memtype(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memtype.get(), H5T_VARIABLE);
    H5Tset_cset(memtype.get(), H5Tget_cset(type.get()));  // h5py writes UTF-8
    char* value = nullptr;
    if (H5Aread(attr.get(), memtype.get(), &value) < 0 || !value)
      fail(where, fmt::format("cannot read attribute '{}'", name));
    std::string out(value);
    H5free_memory(value);
    return out;
  }
  std::string out(H5Tget_size(type.get()), '\0');
  if (H5Aread(attr.get(), type.get(), out.data()) < 0)
    fail(where, fmt::format("cannot read attribute '{}'", name));
  return out.substr(0, out.find('\0'));
}

std::vector<double> read_dataset(hid_t group, const std::string& name, const std::string& where,
                                 std::optional<std::string>& units) {
  const Handle set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid()) fail(where, fmt::format("{} is not a dataset", name));
  const Handle space(H5Dget_space(set.get()), H5Sclose);
  hsize_t n = 0;
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 1 ||
      H5Sget_simple_extent_dims(space.get(), &n, nullptr) < 0)
    fail(where, fmt::format("{} must be a 1-D dataset", name));
  std::vector<double> values(n);
  if (n > 0 && H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
    fail(where, fmt::format("cannot read {} (not numeric, truncated or corrupt)", name));
  units = string_attribute(set.get(), "units", fmt::format("{}/{}", where, name));
  return values;
}

std::vector<std::string> member_names(hid_t group, const std::string& where) {
  H5G_info_t info;
  if (H5Gget_info(group, &info) < 0) fail(where, "cannot read the group");
  std::vector<std::string> names;
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    std::vector<char> name(1024, '\0');
    if (H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size() - 1,
                           H5P_DEFAULT) < 0)
      fail(where, "cannot list the group (corrupt file)");
    names.emplace_back(name.data());
  }
  return names;
}

bool exists(hid_t file, const std::string& path) {
  // Each level must exist before the next can be asked about.
  for (std::size_t slash = path.find('/', 1);; slash = path.find('/', slash + 1)) {
    const std::string prefix = path.substr(0, slash);
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) return true;
  }
}

}  // namespace freestand::hdf5
