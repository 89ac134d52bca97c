// Base shapes (body "base": corner gaps, edge inset): the base nodes of every
// face move as the map of base_shape.h says, checked against what the map
// must reproduce by construction: corners exactly where stated, a planar set
// of gaps as that plane, an inset box as the narrower box (with the node
// areas and first moment of a uniformly pressed base intact), and the side
// faces' nodes on the base edges moving with the base's so that against the
// table they stay one point.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "freestand/input_error.h"
#include "freestand/plane_contact_nodes.h"
#include "freestand/scene.h"

using Eigen::Vector3d;
using freestand::BaseShape;
using freestand::ConvexShape;
using freestand::NodeLayout;
using freestand::NodeOptions;

namespace {

constexpr double kB = 0.3, kD = 0.2, kH = 0.5;  // box half extents

NodeOptions surface(int per_edge, const BaseShape& base) {
  NodeOptions o;
  o.per_edge = per_edge;
  o.layout = NodeLayout::kSurface;
  o.base = base;
  return o;
}

std::vector<freestand::ContactNode> base_nodes(const NodeOptions& options) {
  const freestand::Clump box(ConvexShape::box(Vector3d(kB, kD, kH)));
  NodeOptions base = options;
  base.faces = box.base_faces();
  return freestand::make_contact_nodes(box, base);
}

}  // namespace

TEST(BaseShape, PolygonWeightsReproduceThePointAtCornersEdgesAndInside) {
  const std::vector<Vector3d> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<double> w;
  for (const Vector3d& x : {Vector3d(1, 0, 0), Vector3d(0.25, 0, 0), Vector3d(0.3, 0.6, 0)}) {
    freestand::polygon_weights(square, x, Vector3d::UnitZ(), 1e-12, &w);
    Vector3d sum = Vector3d::Zero();
    double total = 0;
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_GE(w[i], 0.0);
      sum += w[i] * square[i];
      total += w[i];
    }
    EXPECT_NEAR(total, 1.0, 1e-15);
    EXPECT_NEAR((sum - x).norm(), 0.0, 1e-15);
  }
}

TEST(BaseShape, OneShortCornerRisesByItsGapAndTheOppositeEdgesStay) {
  // Corner [1, -1] of the box (x = b, y = -d) short by 1 mm: that corner's
  // node moves up by exactly the gap, nodes on the two edges away from it
  // (x = -b, y = +d) do not move, and every node rises by between 0 and the gap.
  BaseShape shape;
  shape.corner_gaps.push_back({Eigen::Vector2d(1, -1), 1e-3});
  const auto flat = base_nodes(surface(4, {}));
  const auto shaped = base_nodes(surface(4, shape));
  ASSERT_EQ(flat.size(), shaped.size());
  for (std::size_t i = 0; i < flat.size(); ++i) {
    const Vector3d p = flat[i].position, q = shaped[i].position;
    EXPECT_NEAR((q - p).head<2>().norm(), 0.0, 1e-15);
    const double rise = q.z() - p.z();
    if (std::fabs(p.x() - kB) < 1e-12 && std::fabs(p.y() + kD) < 1e-12) EXPECT_NEAR(rise, 1e-3, 1e-15);
    else if (std::fabs(p.x() + kB) < 1e-12 || std::fabs(p.y() - kD) < 1e-12) EXPECT_NEAR(rise, 0.0, 1e-15);
    EXPECT_GE(rise, -1e-15);
    EXPECT_LE(rise, 1e-3 + 1e-15);
  }
}

TEST(BaseShape, GapsInAPlaneMakeThatPlane) {
  // Both +x corners short by g: the base becomes the plane z = g (1 + x/b) / 2.
  BaseShape shape;
  const double g = 2e-3;
  shape.corner_gaps = {{Eigen::Vector2d(1, 1), g}, {Eigen::Vector2d(1, -1), g}};
  for (const auto& node : base_nodes(surface(5, shape)))
    EXPECT_NEAR(node.position.z(), g * (1 + node.position.x() / kB) / 2, 1e-15) << node.position.transpose();
}

TEST(BaseShape, EdgeInsetMakesTheNarrowerBoxAndKeepsAreaAndFirstMoment) {
  // Inset i: the base nodes fill [-(b - i), b - i] x [-(d - i), d - i] as
  // the flat nodes fill the full base (the map is affine on a box), so the
  // corners are at (+-(b - i), +-(d - i)), the areas are unchanged (the
  // stated stiffness stays the base's) and their first moment is still the
  // centre's.
  BaseShape shape;
  const double inset = 0.05;
  shape.edge_inset = inset;
  const auto flat = base_nodes(surface(3, {}));
  const auto shaped = base_nodes(surface(3, shape));
  double area = 0;
  Vector3d moment = Vector3d::Zero();
  for (std::size_t i = 0; i < flat.size(); ++i) {
    const Vector3d& p = flat[i].position;
    const Vector3d expected(p.x() * (kB - inset) / kB, p.y() * (kD - inset) / kD, 0.0);
    EXPECT_NEAR((shaped[i].position - expected).norm(), 0.0, 1e-15);
    EXPECT_EQ(shaped[i].area, flat[i].area);
    area += shaped[i].area;
    moment += shaped[i].area * shaped[i].position;
  }
  EXPECT_NEAR(area, 4 * kB * kD, 1e-15);
  EXPECT_NEAR(moment.norm(), 0.0, 1e-15);
}

TEST(BaseShape, SideNodesOnTheBaseEdgesMoveWithTheBase) {
  // Against the table the box has as many points with a shaped base as with
  // a flat one (the sides' base-edge nodes merged with the base's), and its
  // lowest points are the inset, gapped base corners.
  BaseShape shape;
  shape.edge_inset = 0.02;
  shape.corner_gaps.push_back({Eigen::Vector2d(-1, 1), 1e-3});
  const freestand::Clump box(ConvexShape::box(Vector3d(kB, kD, kH)));
  const Vector3d com(0, 0, kH);
  const auto flat = freestand::make_plane_contact_nodes(box, com, 100, surface(2, {}));
  const auto shaped = freestand::make_plane_contact_nodes(box, com, 100, surface(2, shape));
  EXPECT_EQ(flat.points(), shaped.points());
  int corners = 0;
  for (const Vector3d& p : shaped.point)
    if (std::fabs(std::fabs(p.x()) - (kB - 0.02)) < 1e-12 && std::fabs(std::fabs(p.y()) - (kD - 0.02)) < 1e-12) {
      ++corners;
      const bool short_corner = p.x() < 0 && p.y() > 0;
      EXPECT_NEAR(p.z() + kH, short_corner ? 1e-3 : 0.0, 1e-15);
    }
  EXPECT_EQ(corners, 4);
}

TEST(BaseShape, SceneStatesTheBaseAndBadBasesAreNamed) {
  using nlohmann::json;
  json doc = json::parse(R"({"bodies": [{"name": "block", "shape": "box", "half_extents": [0.3, 0.2, 0.5],
      "base": {"edge_inset": 0.01, "corner_gaps": [{"corner": [1, -1], "gap": 5e-4}]}}]})");
  const auto scene = freestand::parse_scene(doc, "scene.json");
  EXPECT_EQ(scene.bodies[0].nodes.base.edge_inset, 0.01);
  ASSERT_EQ(scene.bodies[0].nodes.base.corner_gaps.size(), 1u);
  EXPECT_EQ(scene.bodies[0].nodes.base.corner_gaps[0].gap, 5e-4);
  auto error = [&](const json& base) {
    json bad = doc;
    bad["bodies"][0]["base"] = base;
    try {
      freestand::parse_scene(bad, "scene.json");
    } catch (const freestand::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error({{"edge_inset", 0.25}}).find("scene.json: body 'block': base: edge_inset 0.25 m is too large"),
            std::string::npos) << error({{"edge_inset", 0.25}});
  EXPECT_NE(error({{"corner_gaps", {{{"corner", {1, 0}}, {"gap", 1e-3}}}}}).find("does not single out"),
            std::string::npos);
  EXPECT_NE(error({{"corner_gaps", {{{"corner", {1, 1}}}}}}).find("'gap' is missing"), std::string::npos);
  EXPECT_NE(error({{"edge_insets", 0.1}}).find("unknown key 'edge_insets'"), std::string::npos);
  EXPECT_NE(error({{"edge_inset", -0.1}}).find("edge_inset must be >= 0"), std::string::npos);
}
