// Scenarios (docs/scenario.md): overrides, the generated input script, and
// errors that name the file and field, before LIGGGHTS starts.

#include <gtest/gtest.h>

#include "freestand/input_error.h"
#include "scenario.h"
#include "temp_dir.h"

using freestand::InputError;
using nlohmann::json;

namespace {

const char* const kBlock = R"({
  "bodies": [{"name": "block", "shape": "box", "half_extents": [0.125, 0.125, 0.5], "mass": 100,
              "nodes": {"layout": "vertices"}}],
  "interfaces": [{"lower": "table", "upper": "block", "mu": 0.6}],
  "simulation": {"duration": 0.5}
})";

// The error message of `body`, or "" if it did not throw InputError.
template <class F>
std::string error_of(F body) {
  try {
    body();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Scenario, OverridesReachNestedFieldsByIndexAndByName) {
  json doc = json::parse(kBlock);
  freestand::apply_override(doc, "simulation.duration=10");
  freestand::apply_override(doc, "interfaces.0.mu=0.45");
  freestand::apply_override(doc, "bodies.block.mass=120.5");
  freestand::apply_override(doc, "table_motion.x.units=g");
  freestand::apply_override(doc, R"(table_motion.x.pga=[0.3,"g"])");
  EXPECT_EQ(doc["simulation"]["duration"], 10);
  EXPECT_EQ(doc["interfaces"][0]["mu"], 0.45);
  EXPECT_EQ(doc["bodies"][0]["mass"], 120.5);
  EXPECT_EQ(doc["table_motion"]["x"]["units"], "g");  // not JSON: kept as a string
  EXPECT_EQ(doc["table_motion"]["x"]["pga"][1], "g");
  EXPECT_NE(error_of([&] { freestand::apply_override(doc, "simulation.duration"); }).find("key=value"),
            std::string::npos);
  EXPECT_NE(error_of([&] { freestand::apply_override(doc, "bodies.statue.mass=1"); }).find("no element 'statue'"),
            std::string::npos);
}

TEST(Scenario, ScriptRunsTheSceneWithTheTableMotionAndAutoTimeStep) {
  const freestand::test::TempDir dir;
  json doc = json::parse(kBlock);
  doc["table_motion"] = {{"x", {{"motion", "sine"}, {"amplitude", {0.2, "g"}}, {"frequency", 2}}}};
  const std::string path = dir.write("s.json", doc.dump());
  const freestand::GeneratedRun run = freestand::generate_run(freestand::read_scenario(path));
  EXPECT_NE(run.script.find("fix             shake all shaketable x sine amplitude 0.2 g frequency 2 plane 0"),
            std::string::npos) << run.script;
  EXPECT_NE(run.script.find("rigid/convex scene scene.json table shake timestep auto"), std::string::npos);
  EXPECT_EQ(run.script.find("pair_style"), std::string::npos);  // one body: no body-on-body contact
  EXPECT_EQ(run.scene["bodies"].size(), 1u);
  EXPECT_EQ(run.settings.duration, 0.5);
}

TEST(Scenario, TablePitchAndABaseThatIsNotFlatReachTheScriptAndScene) {
  const freestand::test::TempDir dir;
  json doc = json::parse(kBlock);
  doc["table_motion"] = {{"pitch", {{"motion", "onesine"}, {"amplitude", {0.2, "rad/s^2"}}, {"frequency", 1}}}};
  doc["bodies"][0]["base"] = {{"edge_inset", 0.01}, {"corner_gaps", {{{"corner", {1, -1}}, {"gap", 5e-4}}}}};
  const freestand::GeneratedRun run = freestand::generate_run(freestand::read_scenario(dir.write("s.json", doc.dump())));
  EXPECT_NE(run.script.find("shaketable pitch onesine amplitude 0.2 rad/s^2 frequency 1 plane 0"), std::string::npos)
      << run.script;
  EXPECT_EQ(run.scene["bodies"][0]["base"]["edge_inset"], 0.01);
  doc["bodies"][0]["base"] = {{"edge_inset", 0.2}};  // wider than the 0.125 m half width
  EXPECT_NE(error_of([&] { freestand::generate_run(freestand::read_scenario(dir.write("b.json", doc.dump()))); })
                .find("body 'block': base: edge_inset 0.2 m is too large"),
            std::string::npos);
}

TEST(Scenario, DurationComesFromTheRecordWhenNotStated) {
  // DUZCE_BOL090.AT2: 5590 samples at 0.01 s (index.csv), so 55.89 s after t = 0.
  const freestand::test::TempDir dir;
  json doc = json::parse(kBlock);
  doc["simulation"].erase("duration");
  doc["table_motion"] = {{"x", {{"record", FREESTAND_SHARED_DATA "/groundmotions/DUZCE_BOL090.AT2"}, {"units", "g"}}}};
  const freestand::GeneratedRun run =
      freestand::generate_run(freestand::read_scenario(dir.write("s.json", doc.dump())));
  EXPECT_NEAR(run.settings.duration, 55.89, 1e-9);
}

TEST(Scenario, MistakesNameTheFileAndField) {
  const freestand::test::TempDir dir;
  auto generate = [&](const json& doc) {
    return error_of([&] { freestand::generate_run(freestand::read_scenario(dir.write("bad.json", doc.dump()))); });
  };
  json doc = json::parse(kBlock);
  doc["table_motion"] = {{"x", {{"motion", "sine"}, {"pgaa", 1}}}};
  EXPECT_NE(generate(doc).find("bad.json: table_motion.x: unknown key 'pgaa'"), std::string::npos);
  doc["table_motion"] = {{"w", {{"motion", "sine"}}}};
  EXPECT_NE(generate(doc).find("axes are x, y, z, roll and pitch"), std::string::npos);
  doc["table_motion"] = {{"x", {{"record", "missing.AT2"}, {"units", "g"}}}};
  EXPECT_NE(generate(doc).find("missing.AT2"), std::string::npos);
  doc = json::parse(kBlock);
  doc["simulation"]["time_step"] = -1;
  EXPECT_NE(generate(doc).find("simulation.time_step"), std::string::npos);
  doc = json::parse(kBlock);
  doc["bodies"][0].erase("half_extents");
  EXPECT_NE(generate(doc).find("half_extents"), std::string::npos);
  EXPECT_NE(error_of([&] { freestand::read_scenario(dir.write("broken.json", "{\"bodies\": [")); })
                .find("broken.json: not valid JSON"),
            std::string::npos);
}

// fix rigid/convex would refuse a step above the scene's critical one; `freestand run` says so
// first, naming the scenario's field, from the same computation (a step just below runs).
TEST(Scenario, AStepTheContactsCannotTakeIsRefusedNamingTheField) {
  const freestand::test::TempDir dir;
  json doc = json::parse(kBlock);
  const std::string path = dir.write("s.json", doc.dump());
  const double critical = freestand::critical_time_step(freestand::read_scenario(path));
  ASSERT_GT(critical, 0.0);
  doc["simulation"]["time_step"] = 1.05 * critical;
  const std::string above = dir.write("above.json", doc.dump());
  const std::string message = error_of([&] { freestand::generate_run(freestand::read_scenario(above)); });
  EXPECT_NE(message.find("above.json: simulation.time_step: timestep"), std::string::npos) << message;
  EXPECT_NE(message.find("critical time step"), std::string::npos) << message;
  doc["simulation"]["time_step"] = 0.95 * critical;
  const std::string below = dir.write("below.json", doc.dump());
  EXPECT_EQ(error_of([&] { freestand::generate_run(freestand::read_scenario(below)); }), "");
  doc["contact"] = {{"stiffness", "stiff"}};
  const std::string bad = dir.write("bad.json", doc.dump());
  EXPECT_NE(error_of([&] { freestand::generate_run(freestand::read_scenario(bad)); }).find("bad.json: contact: stiffness"),
            std::string::npos);
}
