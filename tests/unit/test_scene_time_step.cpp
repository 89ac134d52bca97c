// The contact laws of a scene as fix rigid/convex applies them, and the
// scene's critical time step at rest (freestand/scene_time_step.h).

#include <cmath>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "freestand/contact_time_step.h"
#include "freestand/input_error.h"
#include "freestand/scene.h"
#include "freestand/scene_contact_laws.h"
#include "freestand/scene_time_step.h"

using freestand::SceneContactLaws;
using freestand::SceneDefaults;
using nlohmann::json;

namespace {

// A tower on a pedestal: the table interface states its stiffness and restitution, the joint
// its friction only (stiffness and restitution from the defaults).
json tower_on_pedestal(double table_stiffness, double joint_stiffness) {
  json scene = json::parse(R"({
    "bodies": [
      {"name": "pedestal", "shape": "box", "half_extents": [0.3, 0.3, 0.38], "mass": 1180.0},
      {"name": "tower", "shape": "box", "half_extents": [0.2, 0.2, 0.8], "mass": 850.0,
       "supported_by": "pedestal"}
    ],
    "interfaces": [
      {"lower": "table", "upper": "pedestal", "mu": 0.55, "restitution": 0.4},
      {"lower": "pedestal", "upper": "tower", "mu_s": 0.6, "mu_k": 0.5, "restitution": 0.2}
    ]
  })");
  scene["interfaces"][0]["contact_stiffness"] = table_stiffness;
  scene["interfaces"][1]["contact_stiffness"] = joint_stiffness;
  return scene;
}

double critical(const json& document, const SceneDefaults& defaults = {}) {
  const freestand::Scene scene = freestand::parse_scene(document, "test", defaults);
  return freestand::resting_time_step(scene, SceneContactLaws(scene, defaults)).critical;
}

}  // namespace

TEST(SceneContactLaws, StatedInterfacesMeetTheirBodiesAndTheDefaultsTheRest) {
  SceneDefaults defaults;
  defaults.stiffness_per_area = 2e9;
  const freestand::Scene scene = freestand::parse_scene(tower_on_pedestal(3.6e8, 1e8), "test", defaults);
  const SceneContactLaws laws(scene, defaults);
  EXPECT_NEAR(laws.table(0).params().stiffness_per_area, 3.6e8 / (0.6 * 0.6), 1e-3);
  EXPECT_EQ(laws.table(1).params().stiffness_per_area, 2e9);  // a toppled tower: no stated table interface
  EXPECT_EQ(laws.between(1, 0).params().mu_s, 0.6);
  EXPECT_EQ(&laws.between(0, 1), &laws.between(1, 0));
  // "normal" tangential damping: each law's own normal zeta; a stated value: that one everywhere.
  EXPECT_EQ(laws.table(0).params().tangential_damping_ratio, laws.table(0).damping_ratio());
  EXPECT_EQ(laws.between(0, 1).params().tangential_damping_ratio, laws.between(0, 1).damping_ratio());
  defaults.tangential_damping = 0.3;
  const SceneContactLaws stated(scene, defaults);
  EXPECT_EQ(stated.table(0).params().tangential_damping_ratio, 0.3);
  EXPECT_EQ(stated.table(1).params().tangential_damping_ratio, 0.3);
}

// A linear law's modes scale exactly: omega^2 are the eigenvalues of M^-1 K with K linear in the
// stiffness, and a restitution gives the same zeta at every stiffness, so four times every
// stiffness halves the critical step (to round-off: 1e-9). Stiffening the joint alone a
// hundredfold puts the limit on the joint, with the joint's law.
TEST(SceneTimeStep, ScalesAsOneOverTheRootOfTheStiffnessAndComesFromTheStiffestContact) {
  const double base = critical(tower_on_pedestal(3.6e8, 1e8));
  ASSERT_GT(base, 0.0);
  EXPECT_NEAR(critical(tower_on_pedestal(4 * 3.6e8, 4e8)), base / 2, 1e-9 * base);

  SceneDefaults defaults;
  const freestand::Scene scene = freestand::parse_scene(tower_on_pedestal(3.6e8, 1e10), "test", defaults);
  const SceneContactLaws laws(scene, defaults);
  const freestand::SceneTimeStep step = freestand::resting_time_step(scene, laws);
  EXPECT_EQ(step.law, &laws.between(1, 0));
  EXPECT_LT(step.critical, base / 3);
  // The linear law's accuracy share (contact_time_step.h).
  EXPECT_NEAR(step.recommended, freestand::kLinearTimeStepFraction * step.critical, 1e-12 * step.critical);
}

TEST(SceneDefaultsKeyword, SetsWhatTheFixKeywordsSetAndNamesABadValue) {
  SceneDefaults d;
  EXPECT_TRUE(freestand::set_scene_default(d, "stiffness", "2e9"));
  EXPECT_TRUE(freestand::set_scene_default(d, "restitution", "0.3"));
  EXPECT_TRUE(freestand::set_scene_default(d, "layout", "vertices"));
  EXPECT_TRUE(freestand::set_scene_default(d, "tangential_damping", "0.25"));
  EXPECT_EQ(d.stiffness_per_area, 2e9);
  EXPECT_EQ(d.restitution, 0.3);
  EXPECT_EQ(d.nodes.layout, freestand::NodeLayout::kVertices);
  EXPECT_EQ(d.tangential_damping, 0.25);
  EXPECT_TRUE(freestand::set_scene_default(d, "tangential_damping", "normal"));
  EXPECT_LT(d.tangential_damping, 0.0);
  EXPECT_FALSE(freestand::set_scene_default(d, "colour", "red"));
  for (const auto& [key, value] : {std::pair{"stiffness", "2e9x"}, {"mu", "nan"}, {"law", "cubic"},
                                   {"layout", "random"}, {"tangential_damping", "-1"}}) {
    try {
      freestand::set_scene_default(d, key, value);
      ADD_FAILURE() << key << " " << value << " was accepted";
    } catch (const freestand::InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(key, 0), 0u) << e.what();
    }
  }
}
