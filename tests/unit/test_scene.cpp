// Scene files: the nominal.json vocabulary turned into bodies and interfaces.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "freestand/input_error.h"
#include "freestand/scene.h"

using nlohmann::json;

namespace {

json tower_on_pedestal() {
  return json::parse(R"({
    "bodies": [
      {"name": "pedestal", "shape": "box", "half_extents": [0.3, 0.3, 0.38], "mass": 1180.0},
      {"name": "tower", "shape": "box", "half_extents": [0.2, 0.2, 0.8], "mass": 850.0,
       "supported_by": "pedestal"}
    ],
    "interfaces": [
      {"lower": "table", "upper": "pedestal", "mu": 0.55, "contact_stiffness": 3.6e8},
      {"lower": "pedestal", "upper": "tower", "mu_s": 0.6, "mu_k": 0.5}
    ]
  })");
}

}  // namespace

TEST(Scene, MassGivenGeometryGivesCentroidAndBoxInertia) {
  const auto scene = freestand::parse_scene(tower_on_pedestal(), "test");
  const auto& p = scene.bodies[0];
  // Uniform box: COM at half height, Ixx = m (b^2 + h^2) / 3 with half sizes b, h.
  EXPECT_NEAR(p.com.z(), 0.38, 1e-12);
  EXPECT_NEAR(p.inertia(0, 0), 1180.0 * (0.3 * 0.3 + 0.38 * 0.38) / 3.0, 1e-9);
  EXPECT_NEAR(p.height, 0.76, 1e-12);
}

TEST(Scene, StackedBodyStandsOnTheTopFaceOfItsSupport) {
  const auto scene = freestand::parse_scene(tower_on_pedestal(), "test");
  EXPECT_NEAR(scene.bodies[0].position.z(), 0.0, 1e-12);
  EXPECT_NEAR(scene.bodies[1].position.z(), 0.76, 1e-12);
}

TEST(Scene, StatedStiffnessIsSpreadOverTheBaseArea) {
  const auto scene = freestand::parse_scene(tower_on_pedestal(), "test");
  const auto* table = freestand::find_interface(scene, "table", "pedestal");
  ASSERT_NE(table, nullptr);
  EXPECT_NEAR(table->contact.stiffness_per_area, 3.6e8 / (0.6 * 0.6), 1e-3);
  EXPECT_EQ(table->contact.mu_s, 0.55);
  const auto* upper = freestand::find_interface(scene, "pedestal", "tower");
  ASSERT_NE(upper, nullptr);
  EXPECT_EQ(upper->contact.mu_s, 0.6);
  EXPECT_EQ(upper->contact.mu_k, 0.5);
  EXPECT_FALSE(upper->notes.empty());  // stiffness and restitution defaulted, and said so
}

TEST(Scene, BadInputIsNamed) {
  auto expect_error = [](json doc, const std::string& needle) {
    try {
      freestand::parse_scene(doc, "scene.json");
      FAIL() << "accepted: " << doc.dump();
    } catch (const freestand::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  json doc = tower_on_pedestal();
  doc["bodies"][1]["supported_by"] = "plinth";
  expect_error(doc, "plinth");
  doc = tower_on_pedestal();
  doc["bodies"][0]["shape"] = "sphere";
  expect_error(doc, "sphere");
  doc = tower_on_pedestal();
  doc["bodies"][0]["name"] = "table";
  expect_error(doc, "reserved");
  doc = tower_on_pedestal();
  doc["bodies"][0]["mass"] = -1.0;
  expect_error(doc, "mass");
  doc = tower_on_pedestal();
  doc["interfaces"][0]["mu_s"] = 0.2;
  doc["interfaces"][0]["mu_k"] = 0.5;
  expect_error(doc, "mu");
}

TEST(Scene, HertzInterfaceRestsAtTheLinearOverlapByDefault) {
  json doc = tower_on_pedestal();
  doc["interfaces"][0]["law"] = "hertz";
  const auto scene = freestand::parse_scene(doc, "test");
  const auto* table = freestand::find_interface(scene, "table", "pedestal");
  ASSERT_NE(table, nullptr);
  EXPECT_EQ(table->contact.law, freestand::NormalLaw::kHertz);
  // delta_ref = m g / (k_a A): the pedestal's resting overlap under the linear law.
  EXPECT_NEAR(table->contact.hertz_reference_overlap, 1180.0 * 9.81 / 3.6e8, 1e-15);
  doc["interfaces"][0]["law"] = "plastic";
  EXPECT_THROW(freestand::parse_scene(doc, "test"), freestand::InputError);
}
