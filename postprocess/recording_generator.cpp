#include "recording_generator.h"

#include <fmt/format.h>
#include <liquid/liquid.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "atomic_file.h"
#include "calibration.h"
#include "freestand/body_channels.h"
#include "freestand/ground_motion_reader.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"
#include "freestand/table_motion.h"
#include "results.h"
#include "scenario.h"
#include "signal_tools.h"

namespace freestand {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

void check_keys(const json& object, const std::set<std::string>& allowed, const std::string& where) {
  if (!object.is_object()) fail(where, "expected a JSON object");
  for (const auto& [key, value] : object.items())
    if (!allowed.count(key)) fail(where, fmt::format("unknown field '{}' (docs/diagnose-cases.md)", key));
}

// The table command is sampled, and the actual table motion written, at this
// step (s): fine against every record (>= 5 ms) and the servo bandwidth.
constexpr double kTableStep = 1e-3;
// velocity_friction: the decay constant d_c of mu(v) = mu_k + (mu_s - mu_k) exp(-d_c v):
// friction falls most of the way to mu_k by 0.1 m/s of sliding.
constexpr double kFrictionDecay = 10.0;  // s/m
// sensor_delay_gain: the body channels' gain deviation per second of delay
// (2 % at 10 ms), so that the search shrinks both together.
constexpr double kGainPerDelay = 2.0;    // 1/s
// Magnitudes tried by the search: start, start/2, ... start/2^(kMaxHalvings)
// (friction on a sliding block is concealed only below ~1/100 of the start).
constexpr int kMaxHalvings = 10;
// An effect is in the recording when the ideal detector's deflection
// (effect_deflection) reaches 3: at a 1 % false-alarm rate (z 2.33) it finds
// it 3 times in 4. Below that no diagnosis can be asked to name it.
constexpr double kPresentDeflection = 3.0;

// Seed of a random stream: realisation 0 is the case's own (its seed), the
// scatter realisations 1, 2, ... are the same for every case, so cases on
// the same base and settings share their scatter runs.
unsigned stream_seed(unsigned case_seed, unsigned realisation, unsigned salt) {
  return salt * (realisation == 0 ? 2654435761u + case_seed : realisation);
}

bool is_angle(const std::string& channel) { return channel == "rock_x" || channel == "rock_y" || channel == "twist"; }

// ---- the catalogue ------------------------------------------------------------

enum class Acts { kPhysics, kTable, kMeasurement };

struct Effect {
  EffectInfo info;
  Acts acts;
};

const std::vector<Effect>& effects() {
  static const std::vector<Effect> list = {
      {{"com_eccentricity", "m", 0.04, 0.08, "the target body's centre of mass moved by the magnitude along +x of its frame"},
       Acts::kPhysics},
      {{"restitution", "1", 0.4, 0.8, "every interface's restitution raised by the magnitude (at most 1)"}, Acts::kPhysics},
      {{"interface_stiffness", "1", 9.0, 99.0,
        "the bottom body's table interface stiffness divided by (1 + magnitude): a more compliant contact"},
       Acts::kPhysics},
      {{"static_kinetic_friction", "1", 0.2, 0.2,
        "every interface: mu_s = nominal mu, mu_k = mu - magnitude, an abrupt drop at breakaway"},
       Acts::kPhysics},
      {{"velocity_friction", "1", 0.2, 0.2,
        fmt::format("every interface: mu(v) = mu_k + (mu - mu_k) exp(-{} s/m v), mu_k = mu - magnitude",
                    kFrictionDecay)},
       Acts::kPhysics},
      {{"corner_gap", "m", 0.004, 0.016,
        "the target body's base corner at +x +y short of the base plane by the magnitude (body 'base' option)"},
       Acts::kPhysics},
      {{"edge_inset", "m", 0.02, 0.08,
        "the target body's base edges rounded or crushed: base contact moved inward by the magnitude (body 'base' "
        "option)"},
       Acts::kPhysics},
      {{"table_vertical", "1", 0.2, 0.8,
        "the table also moves vertically, a_z = magnitude * a_x (actuator crosstalk); not in the recorded channels"},
       Acts::kTable},
      {{"table_pitch", "rad/m", 0.02, 0.08,
        "the table pitches, pitch acceleration = magnitude * a_x (table_motion.pitch); not in the recorded channels"},
       Acts::kTable},
      {{"pedestal_compliance", "1", 9.0, 99.0,
        "the interface under the top body of a stack (pedestal-tower) stiffness divided by (1 + magnitude)"},
       Acts::kPhysics},
      {{"sensor_delay_gain", "s", 0.02, 0.08,
        fmt::format("body channels delayed by the magnitude against the table channels and scaled by 1 + {} /s * "
                    "magnitude",
                    kGainPerDelay)},
       Acts::kMeasurement},
  };
  return list;
}

const Effect* find_effect(const std::string& name) {
  for (const Effect& e : effects())
    if (e.info.name == name) return &e;
  return nullptr;
}

// ---- case files ---------------------------------------------------------------

std::string absolute_from(const std::string& folder, const std::string& path) {
  fs::path p(path);
  if (p.is_relative()) p = fs::path(folder) / p;
  return fs::absolute(p).lexically_normal().string();
}

template <typename T>
void read_number(const json& object, const char* key, T* value, const std::string& where) {
  if (!object.contains(key)) return;
  if (!object.at(key).is_number()) fail(where + "." + key, "expected a number");
  *value = object.at(key).get<T>();
}

// ---- signals ------------------------------------------------------------------

// The table command along x, as fix shaketable plays it (the same reader and
// shaping), and its window length.
std::unique_ptr<SampledAxisMotion> table_command(const json& motion) {
  const json column = motion.value("column", json(""));
  RecordSource source{motion.at("record").get<std::string>(), motion.value("format", "auto"),
                      column.is_string() ? column.get<std::string>() : column.dump(), motion.value("units", "")};
  const GroundRecord record = read_ground_record(source);
  if (record.is_velocity) fail(record.source, "a velocity record: the generator needs an acceleration record");
  RecordShaping shaping;
  shaping.scale = motion.value("scale", 1.0);
  shaping.skip = motion.value("skip", 0.0);
  shaping.duration = motion.at("duration").get<double>();
  return shape_record(record.t, record.value, shaping);
}

// y(t - delay) on the same samples (y[0] before the start: at rest).
std::vector<double> delayed(const std::vector<double>& t, const std::vector<double>& y, double delay) {
  std::vector<double> out(y.size());
  for (std::size_t k = 0; k < y.size(); ++k)
    out[k] = t[k] - delay <= t.front() ? y.front() : signal::interpolate(t, y, t[k] - delay);
  return out;
}

// ---- run documents ------------------------------------------------------------

struct Roles {
  std::string top, bottom;  // top: supports nothing; bottom: stands on the table
};

Roles roles(const Scene& scene) {
  Roles r;
  for (const BodySpec& b : scene.bodies) {
    bool supports = false;
    for (const BodySpec& other : scene.bodies) supports |= other.supported_by == b.name;
    if (!supports) r.top = b.name;
    if (b.supported_by == "table" && r.bottom.empty()) r.bottom = b.name;
  }
  return r;
}

SceneDefaults scene_defaults(const json& scenario) {
  SceneDefaults d;
  const json contact = scenario.value("contact", json::object());
  read_number(contact, "stiffness", &d.stiffness_per_area, "contact");
  read_number(contact, "restitution", &d.restitution, "contact");
  read_number(contact, "mu", &d.mu, "contact");
  return d;
}

Scene parse_model(const json& scenario, const std::string& where) {
  json scene = json::object();
  for (const char* key : {"bodies", "interfaces", "gravity"})
    if (scenario.contains(key)) scene[key] = scenario[key];
  return parse_scene(scene, where, scene_defaults(scenario));
}

// The scenario's entry for the interface lower/upper (appended when the
// scenario left it to the defaults).
json& interface_entry(json& document, const InterfaceSpec& spec) {
  for (json& f : document["interfaces"])
    if (f.value("lower", "") == spec.lower && f.value("upper", "") == spec.upper) return f;
  document["interfaces"].push_back({{"lower", spec.lower}, {"upper", spec.upper}});
  return document["interfaces"].back();
}

json& body_entry(json& document, const std::string& name) {
  for (json& b : document["bodies"])
    if (b.value("name", "") == name) return b;
  fail("effect", fmt::format("no body '{}' in the scenario", name));
}

double base_area(const BodySpec& body) {
  double area = 0.0;
  for (const FaceRef& f : body.geometry.base_faces()) area += body.geometry.pieces()[f.piece].faces()[f.face].area;
  return area;
}

const BodySpec& body_spec(const Scene& scene, const std::string& name) {
  for (const BodySpec& b : scene.bodies)
    if (b.name == name) return b;
  fail("effect", fmt::format("no body '{}'", name));
}

// Divides the total stiffness of the interface under `upper` by (1 + m).
json soften_interface(json& document, const Scene& scene, const std::string& upper, double m) {
  for (const InterfaceSpec& f : scene.interfaces) {
    if (f.upper != upper) continue;
    const double nominal = f.contact.stiffness_per_area * base_area(body_spec(scene, upper));
    interface_entry(document, f)["contact_stiffness"] = nominal / (1 + m);
    return {{"interface", f.lower + "/" + f.upper}, {"contact_stiffness_nominal", nominal},
            {"contact_stiffness_truth", nominal / (1 + m)}};
  }
  fail("effect", fmt::format("no interface under body '{}'", upper));
}

// Sets the friction of every interface: mu_s = nominal mu, mu_k = mu - m.
json lower_kinetic_friction(json& document, const Scene& scene, double m, double decay) {
  json changes = json::array();
  for (const InterfaceSpec& f : scene.interfaces) {
    const double mu = f.contact.mu_s, mu_k = std::max(0.0, mu - m);
    json& entry = interface_entry(document, f);
    entry.erase("mu");
    entry["mu_s"] = mu;
    entry["mu_k"] = mu_k;
    entry["friction_decay"] = decay;
    changes.push_back({{"interface", f.lower + "/" + f.upper}, {"mu_s", mu}, {"mu_k", mu_k}, {"friction_decay", decay}});
  }
  return changes;
}

// Applies a physical effect of magnitude m to the truth document; returns
// what changed, for the answer key.
json apply_physics(json& document, const Scene& scene, const std::string& effect, const std::string& target,
                   double m) {
  const Roles r = roles(scene);
  if (effect == "com_eccentricity") {
    const BodySpec& b = body_spec(scene, target);
    const Eigen::Vector3d com = b.com + Eigen::Vector3d(m, 0, 0);
    body_entry(document, target)["com"] = {com.x(), com.y(), com.z()};
    return {{"body", target}, {"com_nominal", {b.com.x(), b.com.y(), b.com.z()}}, {"com_truth", {com.x(), com.y(), com.z()}}};
  }
  if (effect == "restitution") {
    json changes = json::array();
    for (const InterfaceSpec& f : scene.interfaces) {
      const double nominal = f.contact.restitution.value_or(SceneDefaults().restitution);
      const double e = std::min(1.0, nominal + m);
      interface_entry(document, f)["restitution"] = e;
      changes.push_back({{"interface", f.lower + "/" + f.upper}, {"nominal", nominal}, {"truth", e}});
    }
    return changes;
  }
  if (effect == "interface_stiffness") return soften_interface(document, scene, r.bottom, m);
  if (effect == "pedestal_compliance") {
    if (r.top == r.bottom) fail("effect pedestal_compliance", "needs a stack (a body standing on another)");
    return soften_interface(document, scene, r.top, m);
  }
  if (effect == "static_kinetic_friction") return lower_kinetic_friction(document, scene, m, 0.0);
  if (effect == "velocity_friction") return lower_kinetic_friction(document, scene, m, kFrictionDecay);
  if (effect == "corner_gap") {
    body_entry(document, target)["base"] = {{"corner_gaps", {{{"corner", {1.0, 1.0}}, {"gap", m}}}}};
    return {{"body", target}, {"base", body_entry(document, target)["base"]}};
  }
  if (effect == "edge_inset") {
    body_entry(document, target)["base"] = {{"edge_inset", m}};
    return {{"body", target}, {"base", body_entry(document, target)["base"]}};
  }
  fail("effect", fmt::format("'{}' is not a physical effect", effect));
}

// One run of the truth: which perturbation and table realisation, and the
// effect's magnitude (0: none).
struct TruthRun {
  unsigned realisation = 0;  // initial perturbation and table tracking draw
  double magnitude = 0.0;
};

class CaseRunner {
 public:
  CaseRunner(const CaseSpec& spec, const std::string& cache)
      : spec_(spec), cache_(fs::absolute(cache).lexically_normal().string()) {
    std::ifstream in(spec.scenario);
    if (!in) fail(spec.scenario, "cannot open the scenario file");
    base_ = json::parse(in, nullptr, false);
    if (base_.is_discarded() || !base_.is_object()) fail(spec.scenario, "not a JSON object");
    const json step = base_.value("simulation", json::object()).value("time_step", json());
    if (!step.is_number() || !(step.get<double>() > 0))
      fail(spec.scenario + ": simulation.time_step",
           "the generator needs the model's time step as a number (the truth's is a fraction of it)");
    model_step_ = step.get<double>();
    scene_ = parse_model(base_, spec.scenario);
    const Roles r = roles(scene_);
    target_ = spec.effect.body.empty() ? r.top : spec.effect.body;
    body_spec(scene_, target_);  // an unknown target body fails here, before any run
    command_ = table_command(spec.motion);
    if (!spec.motion_y.is_null()) command_y_ = table_command(spec.motion_y);
    duration_ = spec.motion.at("duration").get<double>();
  }

  // The nominal model, driven by the command, sampled at sampling_hz.
  json model_document() const {
    json doc = base_;
    doc["table_motion"] = {{"x", spec_.motion}};
    if (command_y_) doc["table_motion"]["y"] = spec_.motion_y;
    doc["simulation"]["duration"] = duration_;
    doc["simulation"]["output_rate"] = spec_.sampling_hz;
    return doc;
  }

  json truth_document(const TruthRun& run, json* changes) const {
    json doc = base_;
    std::mt19937 random(stream_seed(spec_.seed, run.realisation, 7919u));
    std::normal_distribution<double> normal(0.0, 1.0);
    for (json& b : doc["bodies"]) {
      b["nodes"] = spec_.truth.nodes;
      b["velocity"] = {spec_.perturbation.velocity * normal(random), spec_.perturbation.velocity * normal(random), 0.0};
      const double w = spec_.perturbation.omega;
      b["omega"] = {w * normal(random), w * normal(random), w * normal(random)};
    }
    const std::string& effect = spec_.effect.name;
    const Acts acts = effect == "none" ? Acts::kMeasurement : find_effect(effect)->acts;
    if (acts == Acts::kPhysics && run.magnitude > 0) *changes = apply_physics(doc, scene_, effect, target_, run.magnitude);
    const double table_effect = acts == Acts::kTable ? run.magnitude : 0.0;
    doc["table_motion"] = actual_table(random, effect, table_effect, changes);
    doc["simulation"]["duration"] = duration_;
    doc["simulation"]["time_step"] = model_step_ / spec_.truth.time_step_divisor;
    doc["simulation"]["output_rate"] = spec_.sampling_hz * spec_.sensors.oversample;
    return doc;
  }

  // Runs the documents (cached), `jobs` at a time; results in input order.
  std::vector<Recording> run(const std::vector<json>& documents, int jobs) const {
    std::vector<Recording> out(documents.size());
    std::vector<std::exception_ptr> failures(documents.size());
    std::atomic<std::size_t> next{0};
    auto worker = [&] {
      for (std::size_t i; (i = next++) < documents.size();) {
        try {
          out[i] = run_cached(documents[i]);
        } catch (...) {
          failures[i] = std::current_exception();
        }
      }
    };
    std::vector<std::thread> threads;
    for (int k = 0; k < std::max(1, jobs); ++k) threads.emplace_back(worker);
    for (std::thread& t : threads) t.join();
    for (const std::exception_ptr& f : failures)
      if (f) std::rethrow_exception(f);
    return out;
  }

  const json& base() const { return base_; }
  const std::string& target() const { return target_; }
  double model_step() const { return model_step_; }

 private:
  // The table's actual motion: gain * (command + noise) through the servo, along x and, with a
  // command along y, along y with its own gain and noise (drawn after x's, so a case along x
  // alone draws as before); written to the cache as CSV, named by its content.
  json actual_table(std::mt19937& random, const std::string& effect, double magnitude, json* changes) const {
    const std::vector<double> ax = actual_axis(random, *command_);
    const std::vector<double> ay = command_y_ ? actual_axis(random, *command_y_) : std::vector<double>();
    const bool vertical = magnitude > 0 && effect == "table_vertical", pitch = magnitude > 0 && effect == "table_pitch";
    std::string csv = std::string("t,ax") + (ay.empty() ? "" : ",ay") + (vertical ? ",az" : "") + (pitch ? ",pitch" : "") + "\n";
    for (std::size_t k = 0; k < ax.size(); ++k) {
      csv += fmt::format("{:.6f},{:.10g}", k * kTableStep, ax[k]);
      if (!ay.empty()) csv += fmt::format(",{:.10g}", ay[k]);
      if (vertical || pitch) csv += fmt::format(",{:.10g}", magnitude * ax[k]);
      csv += "\n";
    }
    const std::string path =
        (fs::path(cache_) / fmt::format("table_{:016x}.csv", std::hash<std::string>{}(csv))).string();
    fs::create_directories(cache_);
    if (!fs::exists(path)) write_file_atomically(path, csv);
    auto axis = [&](const char* column, const char* units) {
      return json{{"record", path}, {"format", "csv"}, {"column", column}, {"units", units}};
    };
    json table = {{"x", axis("ax", "m/s^2")}};
    if (!ay.empty()) table["y"] = axis("ay", "m/s^2");
    if (vertical) table["z"] = axis("az", "m/s^2");
    if (pitch) table["pitch"] = axis("pitch", "rad/s^2");
    if (vertical || pitch) *changes = {{"axis", vertical ? "z" : "pitch"}, {"per_unit_of_table_ax", magnitude}};
    return table;
  }

  // One axis of the table as it moved: gain * (command + noise) through the servo, every kTableStep.
  std::vector<double> actual_axis(std::mt19937& random, const SampledAxisMotion& command) const {
    std::normal_distribution<double> normal(0.0, 1.0);
    const double gain = 1.0 + spec_.table.gain_sd * normal(random);
    const std::size_t n = static_cast<std::size_t>(std::ceil(duration_ / kTableStep)) + 1;
    std::vector<double> input(n);
    for (std::size_t k = 0; k < n; ++k)
      input[k] = gain * (command.at(k * kTableStep).acceleration + spec_.table.noise * normal(random));
    return butterworth_lowpass(input, kTableStep, spec_.table.bandwidth_hz, 2);
  }

  Recording run_cached(const json& document) const {
    const std::string text = document.dump();
    const fs::path dir = fs::path(cache_) / fmt::format("run_{:016x}", std::hash<std::string>{}(text));
    const fs::path done = dir / "done";
    if (fs::exists(done)) return results_as_recording(read_results((dir / RunFiles().results).string()));
    Recording r = run_scenario_document(document, dir.string());
    write_file_atomically(done.string(), text);
    return r;
  }

  const CaseSpec& spec_;
  std::string cache_;
  json base_;
  double model_step_ = 0.0;
  Scene scene_;
  std::string target_;
  std::unique_ptr<SampledAxisMotion> command_;
  std::unique_ptr<SampledAxisMotion> command_y_;  // null: the table moves along x alone
  double duration_ = 0.0;
};

// ---- measurement --------------------------------------------------------------

struct Measurement {
  double delay = 0.0, body_gain = 1.0;  // sensor_delay_gain
  bool noise = true;                    // false: the clean signal (for the effect's own size)
};

// The truth (sampled `oversample` times faster) as the lab records it.
Recording measure(const Recording& truth, const CaseSpec& spec, unsigned realisation, const Measurement& m,
                  json* gains) {
  const SensorModel& s = spec.sensors;
  const double fine_step = 1.0 / (spec.sampling_hz * s.oversample);
  const double cutoff = s.lowpass_hz > 0 ? s.lowpass_hz : spec.sampling_hz / 4;
  std::mt19937 gain_random(stream_seed(spec.seed, realisation, 104729u)),
      noise_random(stream_seed(spec.seed, realisation, 1299709u));
  std::normal_distribution<double> normal(0.0, 1.0);
  Recording out;
  for (std::size_t k = 0; k < truth.time.size(); k += s.oversample) out.time.push_back(truth.time[k]);
  auto record = [&](const std::string& name, std::vector<double> values, double noise, bool body) {
    if (body && m.delay > 0) values = delayed(truth.time, values, m.delay);
    const double gain = (body ? m.body_gain : 1.0) * (1.0 + s.gain_sd * normal(gain_random));
    if (gains) (*gains)[name] = gain;
    for (double& v : values) v *= gain;
    values = butterworth_lowpass(values, fine_step, cutoff, s.lowpass_order);
    RecordingChannel c{name, {}};
    for (std::size_t k = 0; k < values.size(); k += s.oversample)
      c.values.push_back(values[k] + (m.noise ? noise * normal(noise_random) : 0.0));
    out.channels.push_back(std::move(c));
  };
  for (const char axis : {'x', 'y'})
    if (const RecordingChannel* a = truth.find(fmt::format("table_a{}", axis))) {
      record(a->name, a->values, s.acceleration, false);
      record(fmt::format("table_d{}", axis), truth.find(fmt::format("table_d{}", axis))->values, s.length, false);
    }
  for (const std::string& body : truth.body_names())
    for (const std::string& channel : channel_names())
      record(body + "." + channel, truth.body_channel(body, channel), is_angle(channel) ? s.angle : s.length, true);
  return out;
}

// What the recording's sidecar says: the nominal model, the sensors, the
// filter and the command, never the effect.
json nominal_sidecar(const json& scenario, const CaseSpec& spec) {
  json nominal = json::object();
  for (const char* key : {"bodies", "interfaces", "gravity"})
    if (scenario.contains(key)) nominal[key] = scenario[key];
  for (json& b : nominal["bodies"]) b.erase("nodes");  // a simulation setting, not a belief
  const json contact = scenario.value("contact", json::object());
  if (contact.contains("restitution"))
    for (json& f : nominal["interfaces"])
      if (!f.contains("restitution")) f["restitution"] = contact["restitution"];
  const SensorModel& s = spec.sensors;
  nominal["sampling_hz"] = spec.sampling_hz;
  nominal["duration"] = spec.motion.at("duration");
  nominal["sensor_noise"] = {{"angle", s.angle}, {"length", s.length}, {"acceleration", s.acceleration}};
  nominal["lowpass"] = {{"type", "butterworth"}, {"order", s.lowpass_order}, {"causal", true},
                        {"cutoff_hz", s.lowpass_hz > 0 ? s.lowpass_hz : spec.sampling_hz / 4}};
  const auto command = [](const json& g, char axis) {
    return fmt::format("command to the table along {}: {} ({}), scale {}, from {} s for {} s", axis,
                       fs::path(g.at("record").get<std::string>()).filename().string(),
                       g.value("units", "as stated in the file"), g.value("scale", 1.0), g.value("skip", 0.0),
                       g.at("duration").get<double>());
  };
  nominal["ground_motion"] =
      spec.motion_y.is_null()
          ? command(spec.motion, 'x') + "; table_ax and table_dx are what the table did"
          : command(spec.motion, 'x') + "; " + command(spec.motion_y, 'y') + "; table_ax, table_dx, table_ay and "
                                                                              "table_dy are what the table did";
  nominal["source"] = "synthetic: freestand generate (docs/diagnose-cases.md)";
  return nominal;
}

// A magnitude tried: the recording with the effect and how it fares.
struct Verdict {
  double magnitude = 0.0;
  Recording recording;
  nlohmann::json changes;      // what the effect changed, for the answer key
  double error_with = 0.0, change = 0.0, effect_rms = 0.0;
  double effect_deflection = 0.0;  // the ideal detector's, against the sensor noise
  bool concealed = false;
};

}  // namespace

// ---- public -------------------------------------------------------------------

Concealment concealment_rule(const std::string& name, const std::string& where) {
  if (name == "paired_change") return Concealment::kPairedChange;
  if (name == "within_scatter") return Concealment::kWithinScatter;
  fail(where, fmt::format("'{}' is neither paired_change nor within_scatter", name));
}

const std::vector<EffectInfo>& effect_catalogue() {
  static const std::vector<EffectInfo> list = [] {
    std::vector<EffectInfo> out;
    for (const Effect& e : effects()) out.push_back(e.info);
    return out;
  }();
  return list;
}

std::vector<double> butterworth_lowpass(const std::vector<double>& y, double dt, double cutoff_hz, int order) {
  const double fc = cutoff_hz * dt;  // liquid: cutoff over the sampling rate
  if (!(fc > 0 && fc < 0.5) || order < 1)
    throw InputError(fmt::format("low-pass: cutoff {} Hz must lie below the Nyquist frequency {} Hz, order >= 1",
                                 cutoff_hz, 0.5 / dt));
  const int sections = (order + 1) / 2;
  std::vector<float> b(3 * sections), a(3 * sections);
  liquid_iirdes(LIQUID_IIRDES_BUTTER, LIQUID_IIRDES_LOWPASS, LIQUID_IIRDES_SOS, order, static_cast<float>(fc), 0.0f,
                1.0f, 60.0f, b.data(), a.data());
  // Second-order sections in double (transposed direct form II), started in
  // steady state at y[0] so a signal already at a level does not ring.
  std::vector<double> out(y.size());
  if (y.empty()) return out;
  const double level = y.front();
  for (std::size_t k = 0; k < y.size(); ++k) out[k] = y[k] - level;
  for (int s = 0; s < sections; ++s) {
    const double b0 = b[3 * s], b1 = b[3 * s + 1], b2 = b[3 * s + 2], a0 = a[3 * s];
    const double a1 = a[3 * s + 1] / a0, a2 = a[3 * s + 2] / a0;
    double z1 = 0.0, z2 = 0.0;
    for (double& v : out) {
      const double x = v, w = (b0 / a0) * x + z1;
      z1 = (b1 / a0) * x - a1 * w + z2;
      z2 = (b2 / a0) * x - a2 * w;
      v = w;
    }
  }
  for (double& v : out) v += level;
  return out;
}

double global_rms_error(const Recording& recording, const Recording& reference) {
  json scene = json::object();
  for (const char* key : {"bodies", "interfaces", "gravity"})
    if (recording.nominal.contains(key)) scene[key] = recording.nominal[key];
  double sum = 0.0;
  long count = 0;
  for (const BodySpec& body : parse_scene(scene, recording.path + " (nominal)").bodies) {
    const double radius = body.geometry.bounding_radius(body.com);
    for (const std::string& channel : channel_names()) {
      const std::vector<double>& r = recording.body_channel(body.name, channel);
      const std::vector<double>& p = reference.body_channel(body.name, channel);
      const double scale = is_angle(channel) ? radius : 1.0;
      for (std::size_t k = 0; k < r.size(); ++k) {
        const double d = (r[k] - signal::interpolate(reference.time, p, recording.time[k])) * scale;
        if (std::isfinite(d)) sum += d * d, ++count;
      }
    }
  }
  if (count == 0) throw InputError(fmt::format("{}: no body channel sample to compare", recording.path));
  return std::sqrt(sum / count);
}

double effect_deflection(const Recording& with, const Recording& without, const SensorModel& sensors) {
  double sum = 0.0;
  for (const std::string& body : with.body_names())
    for (const std::string& channel : channel_names()) {
      const std::vector<double>& w = with.body_channel(body, channel);
      const std::vector<double>& o = without.body_channel(body, channel);
      const double sd = is_angle(channel) ? sensors.angle : sensors.length;
      for (std::size_t k = 0; k < w.size(); ++k) {
        const double z = (w[k] - signal::interpolate(without.time, o, with.time[k])) / sd;
        if (std::isfinite(z)) sum += z * z;
      }
    }
  return std::sqrt(sum);
}

CaseSpec parse_case(const json& f, const std::string& folder, const std::string& where) {
  check_keys(f, {"name", "scenario", "motion", "motion_y", "effect", "sampling_hz", "sensors", "table", "truth", "perturbation",
                 "seed", "description"},
             where);
  CaseSpec c;
  for (const char* key : {"name", "scenario", "motion"})
    if (!f.contains(key)) fail(where, fmt::format("'{}' is missing", key));
  c.name = f.at("name").get<std::string>();
  if (c.name.empty() || c.name.find_first_of("/\\ ") != std::string::npos)
    fail(where + ".name", "must be a plain file stem");
  c.scenario = absolute_from(folder, f.at("scenario").get<std::string>());
  c.motion = f.at("motion");
  check_keys(c.motion, {"record", "units", "format", "column", "scale", "skip", "duration"}, where + ".motion");
  if (!c.motion.contains("record")) fail(where + ".motion", "'record' is missing");
  if (!c.motion.contains("duration") || !(c.motion.at("duration").get<double>() > 0))
    fail(where + ".motion.duration", "the window length (s) is required and must be positive");
  c.motion["record"] = absolute_from(folder, c.motion.at("record").get<std::string>());
  if (f.contains("motion_y")) {
    c.motion_y = f.at("motion_y");
    check_keys(c.motion_y, {"record", "units", "format", "column", "scale", "skip", "duration"}, where + ".motion_y");
    if (!c.motion_y.contains("record")) fail(where + ".motion_y", "'record' is missing");
    if (c.motion_y.value("duration", json()) != c.motion.at("duration"))
      fail(where + ".motion_y.duration", "must be the same window length as motion.duration");
    c.motion_y["record"] = absolute_from(folder, c.motion_y.at("record").get<std::string>());
  }
  if (f.contains("effect")) {
    const json& e = f.at("effect");
    check_keys(e, {"name", "magnitude", "body", "concealment"}, where + ".effect");
    c.effect.name = e.value("name", "none");
    read_number(e, "magnitude", &c.effect.magnitude, where + ".effect");
    c.effect.body = e.value("body", "");
    c.effect.rule = concealment_rule(e.value("concealment", "paired_change"), where + ".effect.concealment");
    if (c.effect.name != "none" && !find_effect(c.effect.name)) {
      std::string names;
      for (const EffectInfo& i : effect_catalogue()) names += (names.empty() ? "" : ", ") + i.name;
      fail(where + ".effect.name", fmt::format("'{}' is not in the catalogue ({}, none)", c.effect.name, names));
    }
    if (c.effect.magnitude == 0) fail(where + ".effect.magnitude", "0 is no effect: use \"name\": \"none\"");
  }
  read_number(f, "sampling_hz", &c.sampling_hz, where);
  read_number(f, "seed", &c.seed, where);
  if (f.contains("sensors")) {
    const json& s = f.at("sensors");
    const std::string w = where + ".sensors";
    check_keys(s, {"angle", "length", "acceleration", "gain_sd", "lowpass_hz", "lowpass_order", "oversample"}, w);
    read_number(s, "angle", &c.sensors.angle, w);
    read_number(s, "length", &c.sensors.length, w);
    read_number(s, "acceleration", &c.sensors.acceleration, w);
    read_number(s, "gain_sd", &c.sensors.gain_sd, w);
    read_number(s, "lowpass_hz", &c.sensors.lowpass_hz, w);
    read_number(s, "lowpass_order", &c.sensors.lowpass_order, w);
    read_number(s, "oversample", &c.sensors.oversample, w);
    if (c.sensors.oversample < 1) fail(w + ".oversample", "must be at least 1");
  }
  if (f.contains("table")) {
    const json& t = f.at("table");
    check_keys(t, {"bandwidth_hz", "gain_sd", "noise"}, where + ".table");
    read_number(t, "bandwidth_hz", &c.table.bandwidth_hz, where + ".table");
    read_number(t, "gain_sd", &c.table.gain_sd, where + ".table");
    read_number(t, "noise", &c.table.noise, where + ".table");
  }
  if (f.contains("truth")) {
    const json& t = f.at("truth");
    check_keys(t, {"nodes", "time_step_divisor"}, where + ".truth");
    if (t.contains("nodes")) c.truth.nodes = t.at("nodes");
    read_number(t, "time_step_divisor", &c.truth.time_step_divisor, where + ".truth");
    if (c.truth.time_step_divisor < 2) fail(where + ".truth.time_step_divisor", "must be at least 2 (a finer step)");
  }
  if (f.contains("perturbation")) {
    const json& p = f.at("perturbation");
    check_keys(p, {"runs", "velocity", "omega"}, where + ".perturbation");
    read_number(p, "runs", &c.perturbation.runs, where + ".perturbation");
    read_number(p, "velocity", &c.perturbation.velocity, where + ".perturbation");
    read_number(p, "omega", &c.perturbation.omega, where + ".perturbation");
    if (c.perturbation.runs < 2) fail(where + ".perturbation.runs", "at least 2 runs are needed for a spread");
  }
  return c;
}

std::vector<CaseSpec> read_case_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open the case file");
  const json doc = json::parse(in, nullptr, false);
  if (doc.is_discarded()) fail(path, "not valid JSON");
  check_keys(doc, {"defaults", "cases", "description"}, path);
  if (!doc.contains("cases") || !doc.at("cases").is_array() || doc.at("cases").empty())
    fail(path, "'cases' must be a non-empty list");
  const std::string folder = fs::path(path).parent_path().string();
  std::vector<CaseSpec> cases;
  std::set<std::string> names;
  for (std::size_t i = 0; i < doc.at("cases").size(); ++i) {
    json fields = doc.value("defaults", json::object());
    fields.merge_patch(doc.at("cases")[i]);
    cases.push_back(parse_case(fields, folder, fmt::format("{}: cases[{}]", path, i)));
    if (!names.insert(cases.back().name).second)
      fail(fmt::format("{}: cases[{}]", path, i), fmt::format("name '{}' used twice", cases.back().name));
  }
  return cases;
}

GeneratedCase generate_case(const CaseSpec& spec, const std::string& cache, int jobs) {
  const CaseRunner runner(spec, cache);
  const std::string& effect = spec.effect.name;
  const Effect* info = find_effect(effect);
  const bool physical = info && info->acts != Acts::kMeasurement;

  // The model, the case's own truth without the effect, and the scatter runs.
  json unused;
  std::vector<json> documents = {runner.model_document(), runner.truth_document({0, 0.0}, &unused)};
  for (int i = 1; i <= spec.perturbation.runs; ++i)
    documents.push_back(runner.truth_document({static_cast<unsigned>(i), 0.0}, &unused));
  const std::vector<Recording> base = runner.run(documents, jobs);
  GeneratedCase out;
  out.model = base[0];
  out.model.nominal = nominal_sidecar(runner.base(), spec);
  auto recorded = [&](const Recording& truth, unsigned realisation, const Measurement& m, json* gains) {
    Recording r = measure(truth, spec, realisation, m, gains);
    r.nominal = out.model.nominal;
    r.path = spec.name;
    return r;
  };
  std::vector<double> scatter_errors;
  for (int i = 1; i <= spec.perturbation.runs; ++i)
    scatter_errors.push_back(global_rms_error(recorded(base[1 + i], i, {}, nullptr), out.model));
  const double scatter = signal::sample_sd(scatter_errors);
  json gains = json::object();
  const Recording without = recorded(base[1], 0, {}, &gains);
  const double error_without = global_rms_error(without, out.model);
  // within_scatter: the case's own draw without the effect is one more of the
  // no-effect draws, and the bound lies one sd above the largest of them, so
  // that every effect concealed by paired_change is concealed by it too.
  const double within_bound =
      std::max(error_without, *std::max_element(scatter_errors.begin(), scatter_errors.end())) + scatter;
  const bool paired = spec.effect.rule == Concealment::kPairedChange;

  // Verdicts on magnitudes, simulated `jobs` at a time.
  auto evaluate = [&](const std::vector<double>& magnitudes) {
    std::vector<json> runs, changes(magnitudes.size());
    for (std::size_t j = 0; j < magnitudes.size(); ++j)
      runs.push_back(physical ? runner.truth_document({0, magnitudes[j]}, &changes[j]) : documents[1]);
    const std::vector<Recording> truths = runner.run(runs, jobs);
    std::vector<Verdict> verdicts;
    for (std::size_t j = 0; j < magnitudes.size(); ++j) {
      Measurement m, clean_without;
      if (!physical) {
        m.delay = magnitudes[j], m.body_gain = 1 + kGainPerDelay * magnitudes[j];
        changes[j] = {{"delay_s", m.delay}, {"body_gain", m.body_gain}};
      }
      Verdict v{magnitudes[j], recorded(truths[j], 0, m, nullptr), changes[j]};
      v.error_with = global_rms_error(v.recording, out.model);
      v.change = v.error_with - error_without;
      Measurement clean = m;
      clean.noise = clean_without.noise = false;
      const Recording clean_with = recorded(truths[j], 0, clean, nullptr);
      const Recording clean_none = recorded(base[1], 0, clean_without, nullptr);
      v.effect_rms = global_rms_error(clean_with, clean_none);
      v.effect_deflection = effect_deflection(clean_with, clean_none, spec.sensors);
      v.concealed = paired ? std::abs(v.change) <= scatter : v.error_with <= within_bound;
      verdicts.push_back(std::move(v));
    }
    return verdicts;
  };
  // The given magnitude; or start, start/2, ... down to the first concealed
  // one, and when that is start itself, 2 start, 4 start, ... up to the
  // catalogue's maximum while concealed. `jobs` magnitudes per batch.
  std::vector<Verdict> tried;
  const Verdict* chosen = nullptr;
  auto climb = [&](const std::vector<double>& ladder, bool down) {
    for (std::size_t first = 0; first < ladder.size(); first += std::max(1, jobs)) {
      const std::size_t last = std::min(ladder.size(), first + std::max(1, jobs));
      for (Verdict& v : evaluate(std::vector<double>(ladder.begin() + first, ladder.begin() + last)))
        tried.push_back(std::move(v));
      for (std::size_t j = tried.size() - (last - first); j < tried.size(); ++j) {
        if (tried[j].concealed && !down) chosen = &tried[j];
        if (tried[j].concealed == down) {
          if (down) chosen = &tried[j];
          return;
        }
      }
    }
  };
  tried.reserve(64);  // `chosen` points into it
  if (info && spec.effect.magnitude > 0) {
    climb({spec.effect.magnitude}, true);
  } else if (info) {
    std::vector<double> down, up;
    for (int h = 0; h <= kMaxHalvings; ++h) down.push_back(info->info.start / std::pow(2.0, h));
    for (double m = 2 * info->info.start; m <= info->info.max * (1 + 1e-12); m *= 2) up.push_back(m);
    climb(down, true);
    if (chosen == &tried.front()) climb(up, false);
  }
  if (info && !chosen)
    throw InputError(fmt::format(
        "case '{}': effect {} is not concealed at magnitude {} {} (RMS error {:.3g} m, change {:.3g} m; perturbed "
        "errors' sd {:.3g} m{}){}",
        spec.name, effect, tried.back().magnitude, info->info.unit, tried.back().error_with, tried.back().change,
        scatter, paired ? "" : fmt::format(", within_scatter bound {:.3g} m", within_bound),
        spec.effect.magnitude > 0 ? ": give a smaller magnitude, or none to search" : ""));
  // Concealed is not absent: the largest concealed magnitude must still be
  // findable by a detector that knows the answer, or the case tests nothing.
  if (chosen && chosen->effect_deflection < kPresentDeflection)
    throw InputError(fmt::format(
        "case '{}': effect {} is absent from the recording at magnitude {} {}: the ideal detector's deflection "
        "against the sensor noise is {:.3g} (< {}; RMS {:.3g} m): the motion does not exercise it, or this build "
        "ignores the option it sets{}",
        spec.name, effect, chosen->magnitude, info->info.unit, chosen->effect_deflection, kPresentDeflection,
        chosen->effect_rms,
        effect == "corner_gap" || effect == "edge_inset" ? " (the body 'base' option)" : ""));
  Verdict none{0.0, without, json::object()};
  none.error_with = error_without, none.concealed = true;
  const Verdict& final_verdict = chosen ? *chosen : none;
  out.recording = final_verdict.recording;

  json attempts = json::array();
  for (const Verdict& v : tried)
    attempts.push_back({{"magnitude", v.magnitude}, {"error_with_effect", v.error_with}, {"change", v.change},
                        {"effect_rms", v.effect_rms}, {"effect_deflection", v.effect_deflection},
                        {"concealed", v.concealed}});
  out.answer = {
      {"case", spec.name},
      {"effect",
       {{"name", effect},
        {"magnitude", final_verdict.magnitude},
        {"unit", info ? info->info.unit : ""},
        {"what", info ? info->info.what : "no effect: the truth differs from the model only in fidelity"},
        {"target_body", runner.target()},
        {"truth_changes", final_verdict.changes}}},
      {"concealment",
       {{"rule", paired ? "paired_change" : "within_scatter"},
        {"criterion",
         std::string(paired ? "|RMS error of the recording with the effect - RMS error of the same recording without "
                              "it| <= sd of the RMS errors of perturbed recordings without it"
                            : "RMS error of the recording with the effect <= the largest RMS error of the recordings "
                              "without it (the same draw and the perturbed ones) + sd of the perturbed ones") +
             "; errors against the nominal model's prediction, all body channels, angles times the body's bounding "
             "radius (m)"},
        {"error_with_effect", final_verdict.error_with},
        {"error_without_effect", error_without},
        {"change", final_verdict.change},
        {"scatter", scatter},
        {"perturbed_errors", scatter_errors},
        {"effect_rms", final_verdict.effect_rms},
        {"effect_deflection", final_verdict.effect_deflection},
        {"concealed", final_verdict.concealed},
        {"tried", attempts}}},
      {"fidelity",
       {{"model", {{"time_step", runner.model_step()}, {"nodes", "as in the scenario"}}},
        {"truth",
         {{"time_step", runner.model_step() / spec.truth.time_step_divisor},
          {"nodes", spec.truth.nodes},
          {"output_hz", spec.sampling_hz * spec.sensors.oversample}}}}},
      {"measurement",
       {{"channel_gains", gains},
        {"noise", out.recording.nominal["sensor_noise"]},
        {"lowpass", out.recording.nominal["lowpass"]}}},
      {"table",
       {{"servo", fmt::format("causal 2nd-order Butterworth, {} Hz", spec.table.bandwidth_hz)},
        {"gain_sd", spec.table.gain_sd},
        {"noise", spec.table.noise}}},
      {"scenario", spec.scenario},
      {"motion", spec.motion},
      {"motion_y", spec.motion_y},
      {"perturbation", {{"runs", spec.perturbation.runs}, {"velocity", spec.perturbation.velocity},
                        {"omega", spec.perturbation.omega}}},
      {"seed", spec.seed}};
  return out;
}

void check_folders_apart(const std::string& recordings, const std::string& answers) {
  const fs::path rec = fs::weakly_canonical(fs::absolute(recordings)), ans = fs::weakly_canonical(fs::absolute(answers));
  auto inside = [](const fs::path& a, const fs::path& b) {  // a is b or below it
    const fs::path relative = a.lexically_relative(b);
    return !relative.empty() && *relative.begin() != "..";
  };
  if (inside(rec, ans) || inside(ans, rec))
    fail(answers, fmt::format("holds what the recordings conceal, so it must be apart from their folder {} "
                              "(not the same, not in it, not holding it)",
                              recordings));
}

void write_case(const GeneratedCase& generated, const std::string& name, const std::string& recordings,
                const std::string& answers) {
  check_folders_apart(recordings, answers);
  const fs::path rec(recordings), ans(answers);
  fs::create_directories(rec);
  fs::create_directories(ans);
  write_recording((rec / name).string(), generated.recording);
  write_recording((ans / (name + ".model")).string(), generated.model);
  write_file_atomically((ans / (name + ".answer.json")).string(), generated.answer.dump(2) + "\n");
}

}  // namespace freestand
