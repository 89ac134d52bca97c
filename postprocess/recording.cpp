#include "recording.h"

#include <fmt/format.h>
#include <hdf5.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include "freestand/ground_motion_reader.h"
#include "atomic_file.h"
#include "csv_cells.h"
#include "hdf5_read.h"
#include "signal_tools.h"
#include "freestand/input_error.h"
#include "freestand/series_file.h"

namespace freestand {
namespace {

using nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool file_exists(const std::string& path) { return std::ifstream(path).good(); }

// ---- what the format knows ------------------------------------------------

// Fields of the format and of the scene vocabulary (src/freestand/scene.cpp),
// plus freestand's documented extensions (docs/recordings.md).
const std::set<std::string> kTopFields = {
    "bodies", "interfaces", "sampling_hz", "sensor_noise", "ground_motion", "gravity",
    "duration", "lowpass", "columns", "table_height", "units", "source"};
const std::set<std::string> kBodyFields = {
    "name", "shape", "half_extents", "radius", "sides", "height", "vertices", "mass", "com",
    "inertia", "supported_by", "density", "position", "orientation", "velocity", "omega",
    "nodes", "pieces"};
const std::set<std::string> kInterfaceFields = {
    "lower", "upper", "mu", "mu_s", "mu_k", "contact_stiffness", "restitution",
    "friction_decay", "law", "hertz_reference_overlap"};

// Pose extension columns <body>.x ... <body>.qz and their units.
const std::map<std::string, std::string> kPoseChannels = {
    {"x", "m"}, {"y", "m"}, {"z", "m"}, {"qw", "1"}, {"qx", "1"}, {"qy", "1"}, {"qz", "1"}};

bool is_table_channel(const std::string& name) {
  return name.size() == 8 && name.compare(0, 6, "table_") == 0 &&
         std::string("avd").find(name[6]) != std::string::npos &&
         std::string("xyz").find(name[7]) != std::string::npos;
}

// The sidecar body a column `<body>.<channel>` belongs to (longest match:
// body names may contain dots), or empty.
std::string body_of(const std::string& column, const std::vector<std::string>& bodies) {
  std::string best;
  for (const std::string& b : bodies)
    if (column.size() > b.size() + 1 && column.compare(0, b.size() + 1, b + ".") == 0 &&
        b.size() > best.size())
      best = b;
  return best;
}

// SI unit of a column, "1" for dimensionless, empty when the format does not define it.
std::string expected_unit(const std::string& column, const std::vector<std::string>& bodies) {
  if (column == "t") return "s";
  if (is_table_channel(column)) return column[6] == 'a' ? "m/s^2" : column[6] == 'v' ? "m/s" : "m";
  const std::string body = body_of(column, bodies);
  if (body.empty()) return {};
  const std::string channel = column.substr(body.size() + 1);
  if (channel == "rock_x" || channel == "rock_y" || channel == "twist") return "rad";
  if (channel == "slide_x" || channel == "slide_y" || channel == "uplift") return "m";
  const auto pose = kPoseChannels.find(channel);
  return pose == kPoseChannels.end() ? std::string() : pose->second;
}

// Spellings of the SI units (lower case, blanks removed).
bool same_unit(std::string stated, const std::string& expected) {
  stated.erase(std::remove_if(stated.begin(), stated.end(),
                              [](unsigned char c) { return std::isspace(c); }),
               stated.end());
  std::transform(stated.begin(), stated.end(), stated.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static const std::map<std::string, std::set<std::string>> aliases = {
      {"s", {"s", "sec", "second", "seconds"}},
      {"m", {"m", "metre", "metres", "meter", "meters"}},
      {"m/s", {"m/s", "ms^-1", "m/sec"}},
      {"m/s^2", {"m/s^2", "m/s2", "m/s/s", "ms^-2"}},
      {"rad", {"rad", "radian", "radians"}},
      {"1", {"1", "-", "", "dimensionless"}}};
  return aliases.at(expected).count(stated) > 0;
}

void check_unit(const std::string& where, const std::string& column, const std::string& stated,
                const std::vector<std::string>& bodies) {
  const std::string expected = expected_unit(column, bodies);
  if (expected.empty() || same_unit(stated, expected)) return;
  fail(where, fmt::format("column '{}' is stated in '{}', but recordings are in SI units: "
                          "expected {}{}", column, stated, expected,
                          expected == "rad" ? " (radians)" : ""));
}

// ---- nominal ----------------------------------------------------------------

void warn_unknown(const json& object, const std::set<std::string>& known,
                  const std::string& where, std::set<std::string>& reported,
                  std::vector<std::string>& warnings) {
  for (const auto& [key, value] : object.items())
    if (!known.count(key) && reported.insert(where + "/" + key).second)
      warnings.push_back(fmt::format("{}: unknown field '{}' ignored", where, key));
}

// Checks the sidecar's structure; returns its body names. Unknown fields
// become warnings (once per field and place, however many bodies carry it).
std::vector<std::string> check_nominal(const json& nominal, const std::string& source,
                                       std::vector<std::string>& warnings) {
  if (!nominal.is_object()) fail(source, "the nominal must be a JSON object");
  if (!nominal.contains("bodies") || !nominal["bodies"].is_array() || nominal["bodies"].empty())
    fail(source, "'bodies' must be a non-empty list");
  std::set<std::string> reported;
  warn_unknown(nominal, kTopFields, source, reported, warnings);
  std::vector<std::string> names;
  for (const json& body : nominal["bodies"]) {
    if (!body.is_object() || !body.contains("name") || !body["name"].is_string())
      fail(source, fmt::format("body {}: 'name' (a string) is missing", names.size() + 1));
    const std::string name = body["name"].get<std::string>();
    if (name.empty() || name == "table" || name.find_first_of(",/") != std::string::npos)
      fail(source, fmt::format("body name '{}' is empty, reserved or contains ',' or '/'", name));
    if (std::count(names.begin(), names.end(), name))
      fail(source, fmt::format("body name '{}' used twice", name));
    names.push_back(name);
    warn_unknown(body, kBodyFields, source + ": bodies[]", reported, warnings);
  }
  if (nominal.contains("interfaces"))
    for (const json& i : nominal["interfaces"])
      if (i.is_object()) warn_unknown(i, kInterfaceFields, source + ": interfaces[]", reported, warnings);
  return names;
}

// "units": "SI", or an object {column: unit}. Anything else is an error.
void check_stated_units(const json& nominal, const std::string& source,
                        const std::vector<std::string>& bodies) {
  if (!nominal.contains("units")) return;
  const json& units = nominal["units"];
  if (units.is_string()) {
    if (units.get<std::string>() != "SI")
      fail(source, fmt::format("'units' is '{}': recordings are in SI units (s, m, rad)",
                               units.get<std::string>()));
    return;
  }
  if (!units.is_object()) fail(source, "'units' must be \"SI\" or {\"column\": \"unit\"}");
  for (const auto& [column, unit] : units.items()) {
    if (!unit.is_string()) fail(source, fmt::format("'units': '{}' must be a string", column));
    check_unit(source, column, unit.get<std::string>(), bodies);
  }
}

json read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open the nominal (sidecar) file");
  try {
    return json::parse(in);
  } catch (const json::parse_error& e) {
    fail(path, fmt::format("not valid JSON: {}", e.what()));
  }
}

json parse_json_text(const std::string& text, const std::string& where) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    fail(where, fmt::format("not valid JSON: {}", e.what()));
  }
}

// ---- checks common to CSV and HDF5 ---------------------------------------------

// Names a sample in messages: "file:line" (CSV) or "file: sample i" (HDF5).
using SampleLocator = std::function<std::string(std::size_t)>;

void check_time(const std::vector<double>& t, const SampleLocator& where) {
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(t[i])) fail(where(i), "time 't' must be a finite number (no lost samples)");
    if (i > 0 && !(t[i] > t[i - 1]))
      fail(where(i), fmt::format("time {} does not increase (previous sample: {})", t[i], t[i - 1]));
  }
}

// Every column is t, a table channel, a channel of a sidecar body or an
// extra column (kept, with a warning); every sidecar body has a column.
void check_columns(Recording& r, const std::vector<std::string>& bodies,
                   const std::string& sidecar, const std::string& where) {
  std::set<std::string> seen, bodies_with_columns;
  for (const RecordingChannel& c : r.channels) {
    if (c.name.empty()) fail(where, "a column has an empty name");
    if (c.name == "t" || !seen.insert(c.name).second)
      fail(where, fmt::format("column '{}' appears twice", c.name));
    if (is_table_channel(c.name)) continue;
    const std::string body = body_of(c.name, bodies);
    const std::size_t dot = c.name.rfind('.');
    if (body.empty() && dot != std::string::npos)
      fail(where, fmt::format("column '{}' names body '{}', which is not in {}", c.name,
                              c.name.substr(0, dot), sidecar));
    if (!body.empty()) bodies_with_columns.insert(body);
    if (expected_unit(c.name, bodies).empty())
      r.warnings.push_back(fmt::format("{}: column '{}' is not a channel of the format; kept as is",
                                       where, c.name));
  }
  for (const std::string& b : bodies)
    if (!bodies_with_columns.count(b))
      fail(sidecar, fmt::format("body '{}' has no column in {} (expected e.g. '{}.rock_x')", b,
                                where, b));
}

// rock_x and rock_y are atan2 values, so |rock| <= pi in radians; more is a
// unit error (degrees). The margin covers rounding of pi in a text file.
void check_rock_range(const Recording& r, const SampleLocator& where) {
  const double bound = M_PI * (1 + 1e-6);
  for (const RecordingChannel& c : r.channels) {
    if (!ends_with(c.name, ".rock_x") && !ends_with(c.name, ".rock_y")) continue;
    for (std::size_t i = 0; i < c.values.size(); ++i)
      if (std::fabs(c.values[i]) > bound)
        fail(where(i), fmt::format("column '{}' = {} exceeds pi: rocking angles are expected in "
                                   "radians (atan2 of the body axis), not degrees", c.name,
                                   c.values[i]));
  }
}

// ---- table channels -----------------------------------------------------

// Trapezoid integral of y from 0 at its first finite sample; lost samples
// are bridged linearly (the trapezoid over the gap) and stay NaN.
std::vector<double> integrate_from_rest(const std::vector<double>& t, const std::vector<double>& y) {
  std::vector<double> out(t.size(), kNaN);
  std::optional<std::size_t> previous;
  double sum = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(y[i])) continue;
    if (previous) sum += 0.5 * (y[i] + y[*previous]) * (t[i] - t[*previous]);
    out[i] = sum;
    previous = i;
  }
  return out;
}

// Derivative of y at its finite samples (second-order differences over the
// finite samples); NaN where y is lost.
std::vector<double> differentiate_finite(const std::vector<double>& t, const std::vector<double>& y,
                                         const std::string& where) {
  std::vector<double> tf, yf;
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::isfinite(y[i])) { tf.push_back(t[i]); yf.push_back(y[i]); index.push_back(i); }
  if (tf.size() < 3) fail(where, "fewer than 3 valid samples to differentiate");
  const std::vector<double> d = differentiate(tf, yf);
  std::vector<double> out(t.size(), kNaN);
  for (std::size_t k = 0; k < index.size(); ++k) out[index[k]] = d[k];
  return out;
}

// The table's travel as it is differentiated: only the frequencies where it exceeds its stated
// noise (sensor_noise.length; signal::cut_noise), which differentiated twice is 12 m/s^2 rms
// for 0.5 mm at 200 Hz. Lost samples are bridged for the spectrum and stay lost. As recorded,
// with a warning, when no noise is stated or the sampling is not uniform (to 1 % of its step).
std::vector<double> travel_to_differentiate(Recording& r, const std::vector<double>& d, char axis) {
  const json stated = r.nominal.value("sensor_noise", json::object());
  const json noise = stated.is_object() ? stated.value("length", json()) : json();
  const double sigma = noise.is_number() ? noise.get<double>() : 0.0;
  const double dt = signal::median_step(r.time);
  bool uniform = true;
  for (std::size_t k = 0; k + 1 < r.time.size(); ++k) uniform &= std::fabs(r.time[k + 1] - r.time[k] - dt) <= 0.01 * dt;
  const auto finite = [](double v) { return std::isfinite(v); };
  const auto first = std::find_if(d.begin(), d.end(), finite), last = std::find_if(d.rbegin(), d.rend(), finite).base();
  const char* as_recorded = !(sigma > 0) ? "no sensor_noise.length stated"
                            : !uniform     ? "sampling not uniform"
                            : last - first < 8 ? "fewer than 8 samples"
                                               : nullptr;
  if (as_recorded) {
    r.warnings.push_back(fmt::format("{}: table_a{} differentiated twice from table_d{} as recorded ({}): its noise is "
                                     "amplified by (2 pi f)^2",
                                     r.path, axis, axis, as_recorded));
    return d;
  }
  const std::size_t from = first - d.begin(), count = last - first;
  const signal::NoiseCut cut = signal::cut_noise(signal::resample_uniform(r.time, d, r.time[from], dt, count), dt, sigma);
  std::vector<double> out = d;
  for (std::size_t k = 0; k < count; ++k)
    if (std::isfinite(d[from + k])) out[from + k] = cut.values[k];
  r.warnings.push_back(fmt::format("{}: table_a{} differentiated twice from table_d{} where the travel exceeds its "
                                   "stated noise ({:.3g} m): up to {:.3g} Hz",
                                   r.path, axis, axis, sigma, cut.highest_kept_hz));
  return out;
}

// Per axis: a missing velocity is integrated from the acceleration (from
// rest) or else differentiated from the displacement (through
// travel_to_differentiate); a missing acceleration is differentiated from
// the velocity; a missing displacement is integrated from the velocity
// (from zero).
void derive_table_channels(Recording& r) {
  for (const char axis : {'x', 'y', 'z'}) {
    const auto values = [&](char kind) -> std::optional<std::vector<double>> {
      const RecordingChannel* c = r.find(fmt::format("table_{}{}", kind, axis));
      return c ? std::optional<std::vector<double>>(c->values) : std::nullopt;
    };
    std::optional<std::vector<double>> a = values('a'), v = values('v'), d = values('d');
    if (!a && !v && !d) continue;
    const auto add = [&](char kind, std::vector<double> derived) {
      r.channels.push_back({fmt::format("table_{}{}", kind, axis), derived, true});
      return derived;
    };
    const std::string where = fmt::format("{}: deriving table channels along {}", r.path, axis);
    if (!v) v = add('v', a ? integrate_from_rest(r.time, *a) : differentiate_finite(r.time, travel_to_differentiate(r, *d, axis), where));
    if (!a) a = add('a', differentiate_finite(r.time, *v, where));
    if (!d) d = add('d', integrate_from_rest(r.time, *v));
  }
}

// A warning per table acceleration with lost samples: a replay bridges them (or refuses).
void report_lost_table_samples(Recording& r) {
  for (const char axis : {'x', 'y', 'z'}) {
    const std::vector<double>* a = r.table_channel('a', axis);
    if (!a) continue;
    const signal::LostSamples lost = signal::lost_samples(r.time, *a);
    if (lost.count == 0) continue;
    r.warnings.push_back(fmt::format("{}: table_a{}: {} samples lost, the longest run spanning {:.3g} s from t = {:.6g} s; "
                                     "a replay of the table bridges runs up to {} s linearly",
                                     r.path, axis, lost.count, lost.longest, lost.longest_at, kLongestTableBridge));
  }
}

// Checks shared by both file kinds, then the derived table channels.
void finish(Recording& r, const std::vector<std::string>& bodies, const std::string& sidecar,
            const SampleLocator& where) {
  check_stated_units(r.nominal, sidecar, bodies);
  check_columns(r, bodies, sidecar, r.path);
  check_time(r.time, where);
  check_rock_range(r, where);
  derive_table_channels(r);
  report_lost_table_samples(r);
}

// ---- CSV ------------------------------------------------------------------

Recording read_csv(const std::string& path, const std::string& sidecar) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open file");
  Recording r;
  r.path = path;
  r.nominal = read_json_file(sidecar);
  const std::vector<std::string> bodies = check_nominal(r.nominal, sidecar, r.warnings);
  std::string text;
  if (!std::getline(in, text)) fail(path, "empty file: expected a header line of column names");
  if (!text.empty() && text.back() == '\r') text.pop_back();
  const std::vector<std::string_view> header = split_cells(text);
  if (header.front() != "t") {
    const bool has_t = std::find(header.begin(), header.end(), "t") != header.end();
    fail(path + ":1", has_t ? "column 't' must come first" : "no time column 't'");
  }
  for (std::size_t c = 1; c < header.size(); ++c) r.channels.push_back({std::string(header[c]), {}});
  std::vector<int> lines;  // file line of each sample
  for (int line = 2; std::getline(in, text); ++line) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (text.find_first_not_of(" \t") == std::string::npos) continue;
    const std::string where = fmt::format("{}:{}", path, line);
    const std::vector<std::string_view> cells = split_cells(text);
    if (cells.size() != header.size())
      fail(where, fmt::format("{} cells, but the header has {} columns", cells.size(), header.size()));
    r.time.push_back(cell_value(cells[0], where, 1, "t"));
    for (std::size_t c = 1; c < cells.size(); ++c)
      r.channels[c - 1].values.push_back(cell_value(cells[c], where, c + 1, r.channels[c - 1].name));
    lines.push_back(line);
  }
  if (r.time.empty()) fail(path, "no samples after the header line");
  finish(r, bodies, sidecar, [&](std::size_t i) { return fmt::format("{}:{}", path, lines[i]); });
  return r;
}

// ---- HDF5 -------------------------------------------------------------------

// The datasets of /channels in name order, checked against each other and
// against their units attributes.
void read_hdf5_channels(hid_t file, Recording& r, const std::vector<std::string>& bodies) {
  const std::string where = r.path + ": /channels";
  if (!hdf5::exists(file, "/channels")) fail(r.path, "group /channels is missing");
  const hdf5::Handle group(H5Gopen2(file, "/channels", H5P_DEFAULT), H5Gclose);
  if (!group.valid()) fail(where, "cannot read the group");
  bool has_time = false;
  for (const std::string& column : hdf5::member_names(group.get(), where)) {
    std::optional<std::string> unit;
    std::vector<double> values = hdf5::read_dataset(group.get(), column, where, unit);
    if (unit) check_unit(where + "/" + column, column, *unit, bodies);
    if (column == "t") {
      r.time = std::move(values);
      has_time = true;
    } else {
      r.channels.push_back({column, std::move(values)});
    }
  }
  if (!has_time) fail(where, "no time dataset 't'");
  if (r.time.empty()) fail(where, "/channels/t is empty");
  for (const RecordingChannel& c : r.channels)
    if (c.values.size() != r.time.size())
      fail(where, fmt::format("'{}' has {} samples, 't' has {}", c.name, c.values.size(),
                              r.time.size()));
}

Recording read_hdf5(const std::string& path) {
  const hdf5::Quiet quiet;
  const hdf5::Handle file(hdf5::open_file(path), H5Fclose);
  Recording r;
  r.path = path;
  const std::string sidecar = path + ": /nominal";
  const std::optional<std::string> nominal = hdf5::string_attribute(file.get(), "nominal", path);
  if (!nominal) fail(path, "attribute /nominal (the nominal JSON text) is missing");
  r.nominal = parse_json_text(*nominal, sidecar);
  const std::vector<std::string> bodies = check_nominal(r.nominal, sidecar, r.warnings);
  read_hdf5_channels(file.get(), r, bodies);
  finish(r, bodies, sidecar, [&](std::size_t i) { return fmt::format("{}: sample {}", path, i); });
  return r;
}

// ---- writing ------------------------------------------------------------------

// The measured (not derived) channels, after checking that the recording
// can be written.
std::vector<const RecordingChannel*> written_channels(const Recording& r, const std::string& stem) {
  if (r.time.empty()) fail(stem, "the recording has no samples");
  std::vector<const RecordingChannel*> out;
  for (const RecordingChannel& c : r.channels) {
    if (c.values.size() != r.time.size())
      fail(stem, fmt::format("channel '{}' has {} samples, time has {}", c.name, c.values.size(),
                             r.time.size()));
    if (c.name.empty() || c.name == "t" || c.name.find_first_of(",/\n") != std::string::npos)
      fail(stem, fmt::format("channel name '{}' is empty, 't', or contains ',', '/' or a newline",
                             c.name));
    if (!c.derived) out.push_back(&c);
  }
  return out;
}

std::string format_value(double x) { return std::isfinite(x) ? fmt::format("{}", x) : "nan"; }

void write_csv(const std::string& stem, const Recording& r,
               const std::vector<const RecordingChannel*>& columns) {
  std::ostringstream text;
  text << 't';
  for (const RecordingChannel* c : columns) text << ',' << c->name;
  text << '\n';
  for (std::size_t i = 0; i < r.time.size(); ++i) {
    text << format_value(r.time[i]);
    for (const RecordingChannel* c : columns) text << ',' << format_value(c->values[i]);
    text << '\n';
  }
  write_file_atomically(stem + ".nominal.json", r.nominal.dump(2) + "\n");
  write_file_atomically(stem + ".csv", text.str());
}

void write_hdf5(const std::string& stem, const Recording& r,
                const std::vector<const RecordingChannel*>& columns) {
  const std::vector<std::string> bodies = r.body_names();
  SeriesFile file(stem + ".h5");
  file.add_series("/channels/t", "s");
  for (const RecordingChannel* c : columns)
    file.add_series("/channels/" + c->name, expected_unit(c->name, bodies));
  file.set_attribute("/", "nominal", r.nominal.dump());
  std::vector<double> row(columns.size() + 1);
  for (std::size_t i = 0; i < r.time.size(); ++i) {
    row[0] = r.time[i];
    for (std::size_t c = 0; c < columns.size(); ++c) row[c + 1] = columns[c]->values[i];
    file.append(row);
  }
  file.commit();
}

}  // namespace

std::vector<std::string> Recording::body_names() const {
  std::vector<std::string> names;
  if (nominal.is_object() && nominal.contains("bodies") && nominal["bodies"].is_array())
    for (const json& b : nominal["bodies"])
      if (b.is_object() && b.contains("name") && b["name"].is_string())
        names.push_back(b["name"].get<std::string>());
  return names;
}

const RecordingChannel* Recording::find(const std::string& name) const {
  for (const RecordingChannel& c : channels)
    if (c.name == name) return &c;
  return nullptr;
}

const std::vector<double>& Recording::body_channel(const std::string& body,
                                                   const std::string& channel) const {
  const RecordingChannel* c = find(body + "." + channel);
  if (!c) fail(path.empty() ? "recording" : path, fmt::format("no column '{}.{}'", body, channel));
  return c->values;
}

const std::vector<double>* Recording::table_channel(char kind, char axis) const {
  const RecordingChannel* c = find(fmt::format("table_{}{}", kind, axis));
  return c ? &c->values : nullptr;
}

std::vector<double> replayed_table_acceleration(const Recording& recording, char axis) {
  const std::vector<double>* a = recording.table_channel('a', axis);
  if (!a) return {};
  if (const signal::LostSamples lost = signal::lost_samples(recording.time, *a); lost.longest > kLongestTableBridge)
    fail(recording.path.empty() ? "recording" : recording.path,
         fmt::format("table acceleration along {} lost for {:.3g} s from t = {:.6g} s: cannot replay the table (a "
                     "replay bridges at most {} s)",
                     axis, lost.longest, lost.longest_at, kLongestTableBridge));
  return signal::bridge_lost(recording.time, *a);
}

Recording up_to(const Recording& recording, double end) {
  Recording out = recording;
  const auto kept = static_cast<std::size_t>(std::upper_bound(out.time.begin(), out.time.end(), end) - out.time.begin());
  out.time.resize(kept);
  for (RecordingChannel& c : out.channels) c.values.resize(std::min(kept, c.values.size()));
  return out;
}

Recording read_recording(const std::string& path) {
  const auto stem_of = [&](std::size_t suffix_length) { return path.substr(0, path.size() - suffix_length); };
  if (ends_with(path, ".csv")) return read_csv(path, stem_of(4) + ".nominal.json");
  if (ends_with(path, ".h5") || ends_with(path, ".hdf5")) return read_hdf5(path);
  for (const char* suffix : {".csv", ".h5", ".hdf5"})
    if (file_exists(path + suffix)) return read_recording(path + suffix);
  fail(path, "no recording: neither PATH.csv, PATH.h5 nor PATH.hdf5 exists");
}

void write_recording(const std::string& path_stem, const Recording& recording, bool hdf5) {
  const std::vector<const RecordingChannel*> columns = written_channels(recording, path_stem);
  std::vector<std::string> warnings;
  check_nominal(recording.nominal, path_stem + ".nominal.json", warnings);
  if (hdf5) write_hdf5(path_stem, recording, columns);
  else write_csv(path_stem, recording, columns);
}

}  // namespace freestand
