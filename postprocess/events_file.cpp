#include "events_file.h"

#include <fmt/format.h>
#include <hdf5.h>

#include <filesystem>

#include "atomic_file.h"
#include "freestand/body_channels.h"
#include "freestand/input_error.h"
#include "hdf5_read.h"

namespace freestand {

namespace fs = std::filesystem;
using hdf5::Handle;

namespace {

void check(herr_t status, const std::string& where) {
  if (status < 0) throw InputError(where + ": cannot write (disk full or file damaged)");
}

hid_t make_group(hid_t parent, const std::string& name, const std::string& where) {
  const hid_t group = H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (group < 0) throw InputError(where + ": cannot create group " + name);
  return group;
}

void string_attribute(hid_t object, const char* name, const std::string& value, const std::string& where) {
  const Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), value.size() + 1);
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle attr(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(attr.valid() ? H5Awrite(attr.get(), type.get(), value.c_str()) : -1, where);
}

void number_attribute(hid_t object, const char* name, double value, const std::string& where) {
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle attr(H5Acreate2(object, name, H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(attr.valid() ? H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, &value) : -1, where);
}

// A 1-D float64 dataset with its units.
void column(hid_t group, const char* name, const std::vector<double>& values, const char* units,
            const std::string& where) {
  const hsize_t n = values.size();
  const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  const Handle set(H5Dcreate2(group, name, H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Dclose);
  if (!set.valid()) throw InputError(fmt::format("{}: cannot create dataset {}", where, name));
  if (n > 0) check(H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), where);
  string_attribute(set.get(), "units", units, where);
}

// A table: one dataset per field, all as long as `rows`.
template <class Row>
void table(hid_t parent, const char* name, const std::vector<Row>& rows,
           const std::vector<std::tuple<const char*, const char*, double Row::*>>& fields, const std::string& where) {
  const Handle group(make_group(parent, name, where), H5Gclose);
  for (const auto& [field, units, member] : fields) {
    std::vector<double> values;
    for (const Row& r : rows) values.push_back(r.*member);
    column(group.get(), field, values, units, where);
  }
}

void write_body(hid_t events, const AnalysedBody& body, const std::string& where) {
  using namespace analysis;
  const MotionSummary& s = body.summary;
  const Handle group(make_group(events, body.name, where), H5Gclose);
  const Handle peaks(make_group(group.get(), "peaks", where), H5Gclose);
  std::vector<double> max, t_max, min, t_min;
  for (const Peak& p : s.peaks) max.push_back(p.max), t_max.push_back(p.t_max), min.push_back(p.min), t_min.push_back(p.t_min);
  column(peaks.get(), "max", max, "rad or m", where);
  column(peaks.get(), "t_max", t_max, "s", where);
  column(peaks.get(), "min", min, "rad or m", where);
  column(peaks.get(), "t_min", t_min, "s", where);
  std::string order;
  for (const std::string& c : channel_names()) order += (order.empty() ? "" : " ") + c;
  string_attribute(peaks.get(), "channels", order, where);
  column(group.get(), "residual", std::vector<double>(s.residual.mean.begin(), s.residual.mean.end()),
         "rad or m", where);
  string_attribute(group.get(), "channels", order, where);
  number_attribute(group.get(), "residual_window_start", s.residual.window_start, where);
  number_attribute(group.get(), "overturned", s.overturn.overturned ? 1.0 : 0.0, where);
  number_attribute(group.get(), "overturn_time", s.overturn.time, where);
  string_attribute(group.get(), "overturn_criterion", s.overturn.criterion, where);

  std::vector<double> start, end, code;
  std::string names;
  for (const ModeSegment& m : s.modes)
    start.push_back(m.start), end.push_back(m.end), code.push_back(static_cast<double>(m.mode));
  for (int m = 0; m <= static_cast<int>(Mode::overturned); ++m)
    names += fmt::format("{}{}={}", m ? " " : "", m, mode_name(static_cast<Mode>(m)));
  const Handle modes(make_group(group.get(), "modes", where), H5Gclose);
  column(modes.get(), "start", start, "s", where);
  column(modes.get(), "end", end, "s", where);
  column(modes.get(), "mode", code, "1", where);
  string_attribute(modes.get(), "mode_codes", names, where);

  for (int axis = 0; axis < 2; ++axis) {
    const RockingImpacts& r = s.impacts[axis];
    table<Impact>(group.get(), axis == 0 ? "impacts_rock_x" : "impacts_rock_y", r.impacts,
                  {{"time", "s", &Impact::time}, {"omega_before", "rad/s", &Impact::omega_before},
                   {"omega_after", "rad/s", &Impact::omega_after}, {"ratio", "1", &Impact::ratio},
                   {"ratio_sd", "1", &Impact::ratio_sd}, {"amplitude_before", "rad", &Impact::amplitude_before},
                   {"amplitude_after", "rad", &Impact::amplitude_after}},
                  where);
  }
  table<SlipEvent>(group.get(), "slips", s.slips,
                   {{"onset", "s", &SlipEvent::onset}, {"stop", "s", &SlipEvent::stop},
                    {"slip_x", "m", &SlipEvent::slip_x}, {"slip_y", "m", &SlipEvent::slip_y},
                    {"peak_speed", "m/s", &SlipEvent::peak_speed}},
                   where);
  table<Separation>(group.get(), "separations", s.separations,
                    {{"start", "s", &Separation::start}, {"end", "s", &Separation::end},
                     {"peak_gap", "m", &Separation::peak_gap}},
                    where);
}

}  // namespace

void write_events(const std::string& results_path, const std::vector<AnalysedBody>& bodies) {
  const std::string part = results_path + ".events.part";
  fs::copy_file(results_path, part, fs::copy_options::overwrite_existing);
  try {
    const hdf5::Quiet quiet;
    const Handle file(H5Fopen(part.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) throw InputError(results_path + ": cannot open for writing events");
    if (hdf5::exists(file.get(), "/events")) check(H5Ldelete(file.get(), "/events", H5P_DEFAULT), results_path);
    const Handle events(make_group(file.get(), "events", results_path), H5Gclose);
    string_attribute(events.get(), "definitions", "docs/postprocessing.md", results_path);
    for (const AnalysedBody& body : bodies) write_body(events.get(), body, results_path + ": /events/" + body.name);
  } catch (...) {
    fs::remove(part);
    throw;
  }
  publish_file(part, results_path);
}

}  // namespace freestand
