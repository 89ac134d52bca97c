// Scene files: the nominal.json vocabulary turned into bodies and interfaces.

#include <cmath>

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
  doc = tower_on_pedestal();
  doc["bodies"][1]["nodes"] = {{"per_edge", 8}, {"refine", "sides"}};
  expect_error(doc, "body 'tower': nodes: refine must be \"all\" or \"bearing\"");
  doc["bodies"][1]["nodes"] = {{"per_edge", 8}, {"spcing", 0.1}};
  expect_error(doc, "body 'tower': nodes: unknown key 'spcing'");
}

TEST(Scene, BearingRefinementCutsTheBaseAndTopFacesOnly) {
  json doc = tower_on_pedestal();
  doc["bodies"][0]["nodes"] = {{"per_edge", 8}, {"refine", "bearing"}};
  const auto scene = freestand::parse_scene(doc, "test");
  const auto& refined = scene.bodies[0].nodes.refined;
  ASSERT_EQ(refined.size(), 2u);
  for (const auto& f : refined)
    EXPECT_NEAR(std::abs(scene.bodies[0].geometry.pieces()[f.piece].faces()[f.face].normal.z()), 1.0, 1e-12);
  EXPECT_TRUE(scene.bodies[1].nodes.refined.empty());
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

namespace {

// Uniform box of half extents (a, b, c) with its base centre at `base`:
// mass, COM and inertia about the COM (diagonal, axis-aligned).
struct BoxPart {
  double m;
  Eigen::Vector3d com;
  Eigen::Matrix3d inertia;
};
BoxPart box_part(double rho, double a, double b, double c, const Eigen::Vector3d& base) {
  const double m = rho * 8 * a * b * c;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  I(0, 0) = m * (b * b + c * c) / 3;
  I(1, 1) = m * (a * a + c * c) / 3;
  I(2, 2) = m * (a * a + b * b) / 3;
  return {m, base + Eigen::Vector3d(0, 0, c), I};
}

// An L-shaped cabinet: a 1.0 x 0.4 x 0.2 m slab and, on its +x end, a
// 0.2 x 0.4 x 0.8 m upright given as a 0.4 x 0.2 x 0.8 m box turned 90
// degrees about z. The upright rests on the slab (they share the face z = 0.2).
json l_shaped(const std::string& upright_extra = "") {
  return json::parse(R"({"bodies": [{"name": "cabinet", "shape": "clump", "density": 2000,
    "pieces": [
      {"shape": "box", "half_extents": [0.5, 0.2, 0.1]},
      {"shape": "box", "half_extents": [0.2, 0.1, 0.4], "offset": [0.4, 0, 0.2],
       "orientation": [0.7071067811865476, 0, 0, 0.7071067811865476])" + upright_extra + R"(}
    ]}]})");
}

}  // namespace

TEST(Scene, ClumpMassPropertiesAreTheSumOfItsParts) {
  const auto scene = freestand::parse_scene(l_shaped(), "test");
  const auto& body = scene.bodies[0];
  ASSERT_EQ(body.geometry.pieces().size(), 2u);
  // Parts by hand: masses add, the COM is the mass-weighted mean, the inertia
  // about the common COM is the sum of each part's own inertia moved by the
  // parallel-axis theorem, I += m (|d|^2 1 - d d^T).
  const BoxPart slab = box_part(2000, 0.5, 0.2, 0.1, Eigen::Vector3d::Zero());
  const BoxPart upright = box_part(2000, 0.1, 0.2, 0.4, Eigen::Vector3d(0.4, 0, 0.2));
  const double m = slab.m + upright.m;  // 160 + 128 kg
  const Eigen::Vector3d com = (slab.m * slab.com + upright.m * upright.com) / m;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (const BoxPart& p : {slab, upright}) {
    const Eigen::Vector3d d = p.com - com;
    inertia += p.inertia + p.m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  // Round-off of the polyhedral integrals is ~1e-15 relative (docs/shapes.md);
  // a wrong placement of the turned piece moves these by > 1e-2.
  EXPECT_NEAR(body.mass, m, 1e-12 * m);
  EXPECT_NEAR((body.com - com).norm(), 0.0, 1e-12);
  EXPECT_NEAR((body.inertia - inertia).norm(), 0.0, 1e-12 * inertia.norm());
  EXPECT_NEAR(body.com.x(), (160 * 0.0 + 128 * 0.4) / 288.0, 1e-12);  // 0.1778 m toward +x
  EXPECT_NEAR(inertia(0, 2), -(160 * (0 - com.x()) * (0.1 - com.z()) +
                               128 * (0.4 - com.x()) * (0.6 - com.z())), 1e-9);  // product I_xz
  EXPECT_NEAR(body.height, 1.0, 1e-12);
  // It stands on the slab's base only.
  const auto base = body.geometry.base_faces();
  ASSERT_EQ(base.size(), 1u);
  EXPECT_EQ(base[0].piece, 0);
}

TEST(Scene, ClumpWithPrismAndConvexPiecesAndStatedMass) {
  // A statue-like clump: an octagonal plinth and a tetrahedral "figure" off centre.
  const auto scene = freestand::parse_scene(json::parse(R"({"bodies": [{"name": "s",
    "shape": "clump", "mass": 500, "pieces": [
      {"shape": "prism", "radius": 0.5, "sides": 8, "height": 0.3},
      {"shape": "convex", "vertices": [[0, 0, 0], [0.3, 0, 0], [0, 0.3, 0], [0, 0, 0.6]],
       "offset": [0.1, 0.1, 0.3]}]}]})"), "test");
  const auto& body = scene.bodies[0];
  EXPECT_NEAR(body.mass, 500.0, 1e-12);
  EXPECT_GT(body.com.x(), 0.0);  // the figure is off centre toward +x, +y
  EXPECT_NEAR(body.com.x(), body.com.y(), 1e-12);
  EXPECT_NEAR(body.height, 0.9, 1e-12);
}

TEST(Scene, BadClumpPieceIsNamed) {
  auto expect_error = [](const json& doc, const std::vector<std::string>& needles) {
    try {
      freestand::parse_scene(doc, "scene.json");
      ADD_FAILURE() << "accepted: " << doc.dump();
    } catch (const freestand::InputError& e) {
      for (const auto& needle : needles)
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  json doc = l_shaped();
  doc["bodies"][0]["pieces"][1].erase("half_extents");
  expect_error(doc, {"body 'cabinet'", "piece 1 (box)", "half_extents"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][1]["half_extents"] = {0.2, -0.1, 0.4};
  expect_error(doc, {"piece 1 (box)", "half_extents"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][0]["shape"] = "sphere";
  expect_error(doc, {"piece 0", "unknown shape 'sphere'"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][1]["shape"] = "clump";
  expect_error(doc, {"piece 1", "cannot itself be a clump"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][1]["offset"] = {0.4, 0, 0.1};  // sinks 0.1 m into the slab
  expect_error(doc, {"body 'cabinet'", "pieces 0 and 1 overlap"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][1]["orientation"] = {1, 1, 0, 0};
  expect_error(doc, {"piece 1 (box)", "unit quaternion"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][1]["offset"] = {0.4, 0};
  expect_error(doc, {"piece 1 (box)", "offset"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][0]["mass"] = 10;
  expect_error(doc, {"piece 0 (box)", "'mass' belongs to the body"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"][1] = {{"shape", "convex"}, {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}};
  expect_error(doc, {"piece 1 (convex)", "at least 4 points"});
  doc = l_shaped();
  doc["bodies"][0]["pieces"] = json::array();
  expect_error(doc, {"body 'cabinet'", "pieces"});
  doc = l_shaped();
  doc["bodies"][0].erase("pieces");
  expect_error(doc, {"body 'cabinet'", "'pieces' is missing"});
}
