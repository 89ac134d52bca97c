#include "scenario.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "freestand/contact_time_step.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"
#include "freestand/scene_contact_laws.h"
#include "freestand/scene_time_step.h"
#include "freestand/shake_table.h"

namespace freestand {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Keys of fix shaketable's per-axis options that a table_motion axis may set
// (docs/fix_shaketable.md); `record` and `motion` choose the source.
const char* const kAxisKeys[] = {"units", "format", "column", "differentiate", "scale", "pga", "skip",
                                 "duration", "baseline", "amplitude", "frequency", "frequency_end", "width"};
const char* const kMotions[] = {"sine", "onesine", "ricker", "rectangle", "sweep"};

json* child(json& node, const std::string& key, const std::string& assignment) {
  if (node.is_array()) {
    const bool index = !key.empty() && std::all_of(key.begin(), key.end(), ::isdigit);
    if (index && std::stoul(key) < node.size()) return &node[std::stoul(key)];
    for (json& element : node)
      if (element.is_object() && element.value("name", "") == key) return &element;
    fail("override '" + assignment + "'", "no element '" + key + "' (an index or a \"name\")");
  }
  if (node.is_null()) node = json::object();  // a new branch
  if (!node.is_object()) fail("override '" + assignment + "'", "'" + key + "' is below a plain value");
  return &node[key];
}

// An option value as fix shaketable reads it: numbers in full precision,
// booleans as yes/no, [value, "unit"] pairs as "value unit".
std::string option_value(const json& value, const std::string& where) {
  if (value.is_boolean()) return value.get<bool>() ? "yes" : "no";
  if (value.is_number()) return fmt::format("{}", value.get<double>());
  if (value.is_string()) {
    const std::string text = value.get<std::string>();
    if (text.empty() || text.find_first_of("\"'#$&") != std::string::npos)
      fail(where, "'" + text + "' cannot be passed to LIGGGHTS (empty, or contains \" ' # $ &)");
    return text;
  }
  if (value.is_array() && value.size() == 2 && value[0].is_number() && value[1].is_string())
    return option_value(value[0], where) + " " + option_value(value[1], where);
  fail(where, "expected a number, a string, true/false or [value, \"unit\"]");
}

// The part of a scenario fix rigid/convex reads as its scene file.
json scene_document(const json& scenario) {
  json scene = json::object();
  for (const char* key : {"bodies", "interfaces", "gravity"})
    if (scenario.contains(key)) scene[key] = scenario[key];
  return scene;
}

// The fix's own check (it would refuse the step), made before LIGGGHTS starts.
void check_scene_time_step(const Scene& scene, const SceneDefaults& defaults, double dt, const std::string& where) {
  const SceneContactLaws laws(scene, defaults);
  const SceneTimeStep step = resting_time_step(scene, laws);
  if (step.law) check_time_step(*step.law, dt, step.critical, where);
}

std::string resolve_path(const Scenario& scenario, const std::string& path) {
  fs::path p(path);
  if (p.is_relative() && !scenario.path.empty()) p = fs::path(scenario.path).parent_path() / p;
  return fs::absolute(p).lexically_normal().string();
}

// fix shaketable arguments of one axis.
std::string axis_arguments(const Scenario& scenario, const std::string& axis, const json& spec) {
  const std::string where = scenario.path + ": table_motion." + axis;
  if (!spec.is_object()) fail(where, "expected an object with \"record\" or \"motion\"");
  std::string args = axis + " ";
  if (spec.contains("record")) {
    const std::string path = resolve_path(scenario, spec.at("record").get<std::string>());
    if (path.find_first_of(" \"'#$&") != std::string::npos)
      fail(where, "record path '" + path + "' contains a space or one of \" ' # $ &: LIGGGHTS cannot take it");
    args += "record " + path;
  } else if (spec.contains("motion")) {
    const std::string motion = spec.at("motion").get<std::string>();
    if (std::find(std::begin(kMotions), std::end(kMotions), motion) == std::end(kMotions))
      fail(where, "motion '" + motion + "' is not one of sine, onesine, ricker, rectangle, sweep");
    args += motion;
  } else {
    fail(where, "needs \"record\": FILE or \"motion\": sine | onesine | ricker | rectangle | sweep");
  }
  for (const auto& [key, value] : spec.items()) {
    if (key == "record" || key == "motion") continue;
    if (std::find(std::begin(kAxisKeys), std::end(kAxisKeys), key) == std::end(kAxisKeys))
      fail(where, "unknown key '" + key + "' (see docs/scenario.md)");
    args += " " + key + " " + option_value(value, where + "." + key);
  }
  return args;
}

// fix shaketable arguments of every axis of the scenario's table_motion ("" for a fixed table).
std::string table_arguments(const Scenario& scenario) {
  std::string table;
  if (!scenario.document.contains("table_motion")) return table;
  for (const auto& [axis, spec] : scenario.document.at("table_motion").items()) {
    if (axis != "x" && axis != "y" && axis != "z" && axis != "roll" && axis != "pitch")
      fail(scenario.path + ": table_motion", "axes are x, y, z, roll and pitch, not '" + axis + "'");
    table += (table.empty() ? "" : " ") + axis_arguments(scenario, axis, spec);
  }
  return table;
}

// The table as fix shaketable will play `table_args` (the same parser and kinematics).
ShakeTable shake_table(const Scenario& scenario, const std::string& table_args) {
  std::vector<std::string> args;
  std::istringstream words(table_args);
  for (std::string w; words >> w;) args.push_back(w);
  try {
    return ShakeTable(parse_shake_table_args(args));
  } catch (const InputError& e) {
    fail(scenario.path + ": table_motion", e.what());
  }
}

// The body extent, for the simulation box: every body's bounding sphere at
// its initial position, padded for rocking, toppling and table travel.
struct Extent {
  double lo[3] = {1e300, 1e300, 1e300};
  double hi[3] = {-1e300, -1e300, -1e300};
};
Extent body_extent(const Scene& scene) {
  Extent e;
  for (const BodySpec& body : scene.bodies) {
    const Eigen::Vector3d centre = body.position + body.orientation * body.com;
    const double r = body.geometry.bounding_radius(body.com);
    for (int k = 0; k < 3; ++k) {
      e.lo[k] = std::min(e.lo[k], centre[k] - r);
      e.hi[k] = std::max(e.hi[k], centre[k] + r);
    }
  }
  return e;
}

// pair_style convex weight: bodies with corner nodes only touch another body
// in one of the two passes (full weight); face grids are seen by both passes
// on flush faces (half weight each). docs/pair_convex.md.
double pass_weight(const Scene& scene) {
  for (const BodySpec& body : scene.bodies)
    if (body.nodes.layout != NodeLayout::kVertices) return 0.5;
  return 1.0;
}

// How far the table goes: the motion as fix shaketable will play it (the same
// parser and kinematics), sampled every 10 ms, so the box holds the bodies
// wherever the table carries them; and the motion's own length.
struct TableTravel {
  double reach[3] = {0, 0, 0};  // largest |displacement| per axis over the run (m)
  double duration = 0.0;        // longest axis of the motion (s)
};
TableTravel table_travel(const Scenario& scenario, const std::string& table_args, double duration) {
  TableTravel travel;
  if (table_args.empty()) return travel;
  const ShakeTable table = shake_table(scenario, table_args);
  travel.duration = table.duration();
  const double end = duration > 0 ? duration : travel.duration;
  for (double t = 0; t <= end + 0.01; t += 0.01) {
    const Eigen::Vector3d d = table.at(t).displacement;
    for (int k = 0; k < 3; ++k) travel.reach[k] = std::max(travel.reach[k], std::fabs(d[k]));
  }
  return travel;
}

}  // namespace

std::optional<ShakeTable> commanded_table(const Scenario& scenario) {
  const std::string args = table_arguments(scenario);
  if (args.empty()) return std::nullopt;
  return shake_table(scenario, args);
}

void apply_override(json& document, const std::string& assignment) {
  const std::size_t equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0)
    fail("override '" + assignment + "'", "expected key=value, e.g. simulation.duration=10");
  const std::string key = assignment.substr(0, equals), text = assignment.substr(equals + 1);
  json* node = &document;
  std::stringstream path(key);
  for (std::string part; std::getline(path, part, '.');) {
    if (part.empty()) fail("override '" + assignment + "'", "empty key part");
    node = child(*node, part, assignment);
  }
  const json parsed = json::parse(text, nullptr, false);
  *node = parsed.is_discarded() ? json(text) : parsed;
}

Scenario read_scenario(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open the scenario file");
  Scenario scenario;
  scenario.path = path;
  try {
    scenario.document = json::parse(in);
  } catch (const json::parse_error& e) {
    fail(path, std::string("not valid JSON: ") + e.what());
  }
  if (!scenario.document.is_object()) fail(path, "a scenario is a JSON object");
  for (const std::string& o : overrides) apply_override(scenario.document, o);
  return scenario;
}

SceneDefaults contact_defaults(const Scenario& scenario) {
  SceneDefaults defaults;
  const json contact = scenario.document.value("contact", json::object());
  if (!contact.is_object()) fail(scenario.path + ": contact", "expected an object (see docs/scenario.md)");
  for (const auto& [key, value] : contact.items()) {
    const std::string where = scenario.path + ": contact." + key;
    bool known = false;
    try {
      known = set_scene_default(defaults, key, option_value(value, where));
    } catch (const InputError& e) {
      fail(scenario.path + ": contact", e.what());
    }
    if (!known) fail(scenario.path + ": contact", "unknown key '" + key + "' (see docs/scenario.md)");
  }
  return defaults;
}

Scene run_scene(const Scenario& scenario) {
  return parse_scene(scene_document(scenario.document), scenario.path, contact_defaults(scenario));
}

double critical_time_step(const Scenario& scenario) {
  const SceneDefaults defaults = contact_defaults(scenario);
  const Scene scene = parse_scene(scene_document(scenario.document), scenario.path, defaults);
  return resting_time_step(scene, SceneContactLaws(scene, defaults)).critical;
}

double step_share(const json& document) {
  const json step = document.value("simulation", json::object()).value("time_step", json());
  if (!step.is_number()) return 0.0;
  const double critical = critical_time_step({"scenario", document, {}});
  return critical > 0 ? step.get<double>() / critical : 0.0;
}

void keep_step_share(json& document, double share) {
  const json step = document.value("simulation", json::object()).value("time_step", json());
  if (!(share > 0) || !step.is_number()) return;
  const double critical = critical_time_step({"scenario", document, {}});
  if (critical > 0 && step.get<double>() > share * critical * (1 + 1e-9)) document["simulation"]["time_step"] = share * critical;
}

RunSettings run_settings(const Scenario& scenario) {
  const json& doc = scenario.document;
  const json sim = doc.value("simulation", json::object());
  const std::string where = scenario.path + ": simulation";
  RunSettings s;
  if (sim.contains("duration")) s.duration = sim.at("duration").get<double>();
  else if (doc.contains("duration")) s.duration = doc.at("duration").get<double>();
  const json step = sim.value("time_step", json("auto"));
  s.time_step = step.is_number() ? fmt::format("{}", step.get<double>()) : step.get<std::string>();
  if (s.time_step != "auto" && !(step.is_number() && step.get<double>() > 0))
    fail(where + ".time_step", "must be \"auto\" or a positive number of seconds");
  s.output_rate = sim.value("output_rate", doc.value("sampling_hz", 200.0));
  if (!(s.output_rate > 0)) fail(where + ".output_rate", "must be positive (samples per second)");
  s.processes = sim.value("processes", 1);
  if (s.processes < 1) fail(where + ".processes", "must be at least 1");
  return s;
}

GeneratedRun generate_run(const Scenario& scenario, const RunFiles& files) {
  const json& doc = scenario.document;
  GeneratedRun run;
  run.settings = run_settings(scenario);
  // The scene (bodies, interfaces, gravity) and the contact defaults, checked now so that a
  // bad body or a step the contacts cannot take is reported against the scenario file before
  // LIGGGHTS starts.
  run.scene = scene_document(doc);
  const SceneDefaults defaults = contact_defaults(scenario);
  const Scene scene = parse_scene(run.scene, scenario.path, defaults);
  if (run.settings.time_step != "auto") check_scene_time_step(scene, defaults, std::stod(run.settings.time_step),
                                                                 scenario.path + ": simulation.time_step");

  const std::string table = table_arguments(scenario),
                    table_height = fmt::format("{}", doc.value("table_height", 0.0));
  const TableTravel travel = table_travel(scenario, table, run.settings.duration);
  if (run.settings.duration <= 0) run.settings.duration = travel.duration;
  if (!(run.settings.duration > 0))
    fail(scenario.path, "no simulation.duration, and no recorded table motion to take it from");

  std::string contact;
  const json stated = doc.value("contact", json::object());
  for (const auto& [key, value] : stated.items())
    contact += " " + key + " " + option_value(value, scenario.path + ": contact." + key);
  Extent e = body_extent(scene);
  for (int k = 0; k < 3; ++k) e.lo[k] -= travel.reach[k], e.hi[k] += travel.reach[k];  // the bodies ride the table
  const double reach = std::max({e.hi[2] - std::min(e.lo[2], 0.0), 1.0});  // room to topple
  const bool moving = !table.empty();

  std::string s;
  s += fmt::format("# Generated by `freestand run` from {}.\n", scenario.path);
  s += "# Edit and rerun: freestand-lmp -in " + files.script + "   (docs/scenario.md)\n";
  s += fmt::format("variable duration index {}   # simulated time [s]\n", run.settings.duration);
  s += fmt::format("variable rate     index {}   # results samples per simulated second\n\n",
                   run.settings.output_rate);
  s += "atom_style      sphere\natom_modify     map array sort 0 0.0\nboundary        f f f\n"
       "newton          off\ncommunicate     single vel yes\nunits           si\nprocessors      * 1 1\n";
  s += fmt::format("region          domain block {:.6g} {:.6g} {:.6g} {:.6g} {:.6g} {:.6g} units box\n",
                   e.lo[0] - reach - 1, e.hi[0] + reach + 1, e.lo[1] - reach - 1, e.hi[1] + reach + 1,
                   std::min(e.lo[2], 0.0) - reach, e.hi[2] + reach);
  s += "create_box      1 domain\n";
  s += fmt::format("neighbor        {:.3g} bin\nneigh_modify    delay 0\n", 0.05);
  s += fmt::format("timestep        {}\n\n", run.settings.time_step == "auto" ? "1e-5   # replaced: timestep auto"
                                                                                : run.settings.time_step);
  if (moving) s += "fix             shake all shaketable " + table + " plane " + table_height + "\n";
  s += "fix             bodies all rigid/convex scene " + files.scene +
       (moving ? " table shake" : " plane " + table_height) + contact +
       (run.settings.time_step == "auto" ? " timestep auto" : "") + "\n";
  if (scene.bodies.size() > 1)
    s += fmt::format("pair_style      convex pass_weight {:g}\npair_coeff      * *\n", pass_weight(scene));
  s += fmt::format("fix             grav all gravity {} vector 0 0 -1\n", scene.gravity);
  s += std::string("compute         rs all rockslide bodies") + (moving ? " table shake" : "") + "\n";
  s += "run             0 post no      # settles dt (timestep auto) before the step count\n";
  s += "variable        nsteps equal round(v_duration/dt)\n"
       "variable        nout equal round(1/(v_rate*dt))+(round(1/(v_rate*dt))<1)\n"
       "variable        nthermo equal ceil(v_nsteps/100)\n";
  s += "fix             h5 all rockslide/hdf5 rs ${nout} " + files.results + " energy bodies contacts bodies scenario " +
       files.scenario + "\n";
  s += "thermo_style    custom step time f_bodies[1] cpu\nthermo          ${nthermo}\n";
  s += "print           \"freestand: steps ${nsteps}\"\n";
  s += "run             ${nsteps}\n";
  run.script = s;
  return run;
}

}  // namespace freestand
