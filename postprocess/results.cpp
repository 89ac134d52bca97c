#include "results.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>

#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "hdf5_read.h"

namespace freestand {

using nlohmann::json;

namespace {

// Every dataset of `group` (a path that exists), each as long as `length`.
std::map<std::string, Series> read_group(hid_t file, const std::string& group_path, std::size_t length,
                                         const std::string& path) {
  const std::string where = path + ": " + group_path;
  const hdf5::Handle group(H5Gopen2(file, group_path.c_str(), H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail(where, "is not a group");
  std::map<std::string, Series> out;
  for (const std::string& name : hdf5::member_names(group.get(), where)) {
    std::optional<std::string> units;
    Series values = hdf5::read_dataset(group.get(), name, where, units);
    if (values.size() != length)
      fail(where + "/" + name, fmt::format("has {} samples, /time has {}", values.size(), length));
    out.emplace(name, std::move(values));
  }
  return out;
}

}  // namespace

const Series& BodyResults::at(const std::string& key) const {
  const auto it = series.find(key);
  if (it == series.end()) throw InputError(fmt::format("body '{}': no series '{}' in the results", name, key));
  return it->second;
}

const BodyResults& Results::body(const std::string& name) const {
  for (const BodyResults& b : bodies)
    if (b.name == name) return b;
  throw InputError(fmt::format("{}: no body '{}' in the results", path, name));
}

double Results::time_step() const {
  const auto it = attributes.find("time_step");
  return it == attributes.end() ? 0.0 : std::strtod(it->second.c_str(), nullptr);
}

Results read_results(const std::string& path) {
  const hdf5::Quiet quiet;
  const hdf5::Handle file(hdf5::open_file(path), H5Fclose);
  Results r;
  r.path = path;
  for (const char* name : {"creator", "channel_definitions", "freestand_version", "liggghts_version",
                           "time_step"})
    if (auto value = hdf5::string_attribute(file.get(), name, path)) r.attributes[name] = *value;
  if (auto text = hdf5::string_attribute(file.get(), "scenario", path)) {
    r.scenario = json::parse(*text, nullptr, false);
    if (r.scenario.is_discarded()) fail(path, "attribute 'scenario' is not valid JSON");
  }
  if (!hdf5::exists(file.get(), "/time")) fail(path, "no /time dataset: not a freestand results file");
  std::optional<std::string> units;
  r.time = hdf5::read_dataset(file.get(), "/time", path, units);
  if (r.time.empty()) fail(path, "/time is empty (the run wrote no sample)");
  if (hdf5::exists(file.get(), "/table")) r.table = read_group(file.get(), "/table", r.time.size(), path);
  if (hdf5::exists(file.get(), "/energy")) r.energy = read_group(file.get(), "/energy", r.time.size(), path);
  if (!hdf5::exists(file.get(), "/bodies")) fail(path, "no /bodies group");
  const hdf5::Handle bodies(H5Gopen2(file.get(), "/bodies", H5P_DEFAULT), H5Gclose);
  for (const std::string& name : hdf5::member_names(bodies.get(), path + ": /bodies"))
    r.bodies.push_back({name, read_group(file.get(), "/bodies/" + name, r.time.size(), path)});
  return r;
}

Recording results_as_recording(const Results& results) {
  Recording rec;
  rec.path = results.path;
  rec.time = results.time;
  rec.nominal = json::object();
  for (const char* key : {"bodies", "interfaces", "gravity"})
    if (results.scenario.is_object() && results.scenario.contains(key)) rec.nominal[key] = results.scenario[key];
  if (!rec.nominal.contains("bodies")) {
    rec.nominal["bodies"] = json::array();
    for (const BodyResults& b : results.bodies) rec.nominal["bodies"].push_back({{"name", b.name}});
  }
  // Table channels of the axes along which the table moved.
  for (const char* axis : {"x", "y", "z"}) {
    const auto moved = results.table.find(std::string("d") + axis);
    if (moved == results.table.end() ||
        std::all_of(moved->second.begin(), moved->second.end(), [](double d) { return d == 0.0; }))
      continue;
    for (const char* kind : {"a", "v", "d"})
      rec.channels.push_back({fmt::format("table_{}{}", kind, axis), results.table.at(std::string(kind) + axis)});
  }
  for (const BodyResults& b : results.bodies) {
    for (const std::string& channel : channel_names()) rec.channels.push_back({b.name + "." + channel, b.at(channel)});
    for (const char* pose : {"x", "y", "z", "qw", "qx", "qy", "qz"})
      if (b.has(pose)) rec.channels.push_back({b.name + "." + pose, b.at(pose)});
  }
  return rec;
}

}  // namespace freestand
