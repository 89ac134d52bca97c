#ifndef FREESTAND_POST_SCENARIO_H
#define FREESTAND_POST_SCENARIO_H

// A scenario: what `freestand run` simulates (docs/scenario.md). Its bodies
// and interfaces are those of a recording's nominal.json (so a recording's
// sidecar plus a table motion is a scenario); `table_motion`, `contact` and
// `simulation` say how the table moves, what is assumed where the bodies
// state nothing, and how to run. The scenario becomes a readable LIGGGHTS
// input script for freestand-lmp.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "freestand/scene.h"
#include "freestand/shake_table.h"

namespace freestand {

struct Scenario {
  std::string path;           // file it was read from; relative paths in it resolve from its folder
  nlohmann::json document;    // the scenario, overrides applied
  std::vector<std::string> notes;  // defaults applied and fields ignored, for the user
};

// Reads a scenario file and applies `overrides` ("key=value", key a dotted
// path such as simulation.duration, interfaces.0.mu or bodies.tower.mass:
// array elements by index or by "name"; value JSON if it parses, else a
// string). Throws InputError naming the file, field or override at fault.
Scenario read_scenario(const std::string& path, const std::vector<std::string>& overrides = {});
void apply_override(nlohmann::json& document, const std::string& assignment);

// The table motion the scenario commands, as fix shaketable will play it
// (the same parser and kinematics); nothing for a fixed table. Throws
// InputError naming the scenario's table_motion when it is wrong.
std::optional<ShakeTable> commanded_table(const Scenario& scenario);

// What fix rigid/convex assumes where the scene states nothing: the scenario's
// `contact` block (docs/scenario.md) over SceneDefaults. Throws InputError
// naming the key at fault.
SceneDefaults contact_defaults(const Scenario& scenario);

// The scene fix rigid/convex will read: the scenario's bodies, interfaces and
// gravity, with its contact defaults. Throws InputError naming the field.
Scene run_scene(const Scenario& scenario);

// The critical time step (s) of the scenario's scene at rest, as fix
// rigid/convex computes it (freestand/scene_time_step.h); 0 when no body
// rests on a base.
double critical_time_step(const Scenario& scenario);

// The share of its critical step a scenario document's numeric time step is;
// 0 for "auto" or a scene without a base (nothing to keep).
double step_share(const nlohmann::json& document);

// A variant of a model with a stiffer or more damped contact (a candidate of
// diagnose, a point of calibrate) rings faster than the model: at the model's
// step fix rigid/convex may refuse it, or resolve its impacts more coarsely.
// Sets the document's step to `share` (the model's step_share) of its own
// critical step when it is coarser than that; a variant the model's step
// allows keeps it, unchanged. share <= 0: nothing changes.
void keep_step_share(nlohmann::json& document, double share);

// How to run it, with defaults resolved (docs/scenario.md).
struct RunSettings {
  double duration = 0.0;        // simulated time (s)
  std::string time_step;        // "auto" (the fix's accurate step) or a number in s, as text
  double output_rate = 0.0;     // samples per simulated second in results.h5 (Hz)
  int processes = 1;            // MPI ranks
};
RunSettings run_settings(const Scenario& scenario);

// Names of the files a run writes in its directory.
struct RunFiles {
  std::string script = "run.in";          // the LIGGGHTS input script
  std::string scene = "scene.json";       // bodies and interfaces for fix rigid/convex
  std::string scenario = "scenario.json"; // the scenario as run (overrides applied)
  std::string results = "results.h5";
};

// The input script (and the scene it reads), ready to be written into the
// run directory. Paths of records are made absolute.
struct GeneratedRun {
  std::string script;          // text of RunFiles::script
  nlohmann::json scene;        // content of RunFiles::scene
  RunSettings settings;
};
GeneratedRun generate_run(const Scenario& scenario, const RunFiles& files = {});

}  // namespace freestand

#endif
