// Contact nodes against the table plane on every face: whatever face a body
// lies on, the acting nodes of that face carry exactly its area and first
// moment (the exactness of docs/shapes.md), and a body on its base presses
// with the base face's shares only.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "freestand/plane_contact_nodes.h"

using Eigen::Vector3d;
using freestand::Clump;
using freestand::ConvexShape;
using freestand::NodeLayout;
using freestand::NodeOptions;
using freestand::PlaneContactNodes;

namespace {

struct Acting {
  double area = 0.0;           // sum of acting shares' areas on points of the lowest plane
  Vector3d moment = Vector3d::Zero();  // their first moment, from the COM
  int points = 0;              // points in that plane
};

// The shares acting at the points that lie in the body's lowest plane for
// world-up `up` (body frame): the face the body rests on.
Acting acting_on_lowest_plane(const PlaneContactNodes& nodes, const Vector3d& up) {
  double lowest = 1e300;
  for (const Vector3d& p : nodes.point) lowest = std::min(lowest, p.dot(up));
  Acting out;
  std::vector<int> acting(16);
  for (std::size_t k = 0; k < nodes.points(); ++k) {
    if (nodes.point[k].dot(up) > lowest + 1e-12) continue;
    ++out.points;
    const int n = nodes.acting_shares(k, up, acting.data());
    for (int s = 0; s < n; ++s) {
      out.area += nodes.area[acting[s]];
      out.moment += nodes.area[acting[s]] * nodes.point[k];
    }
  }
  return out;
}

NodeOptions layout(NodeLayout l, int per_edge = 1) {
  NodeOptions o;
  o.layout = l;
  o.per_edge = per_edge;
  return o;
}

}  // namespace

TEST(PlaneContactNodes, BoxCornersAreSharedByThreeFacesBasePointsFirst) {
  const Clump box(ConvexShape::box({0.25, 0.25, 0.5}));
  const Vector3d com(0, 0, 0.5);
  const PlaneContactNodes nodes = make_plane_contact_nodes(box, com, 100.0, layout(NodeLayout::kVertices));
  ASSERT_EQ(nodes.points(), 8u);
  EXPECT_EQ(nodes.shares(), 24u);
  for (std::size_t k = 0; k < 8; ++k) {
    EXPECT_EQ(nodes.first_share[k + 1] - nodes.first_share[k], 3);
    if (k < 4) {  // the base's corners come first, their base share first
      EXPECT_NEAR(nodes.point[k].z(), -0.5, 1e-15);
      EXPECT_NEAR(nodes.normal[nodes.first_share[k]].z(), -1.0, 1e-15);
      // dashpot mass: the body's share behind the node, m A / A_face
      EXPECT_NEAR(nodes.dashpot_mass[nodes.first_share[k]], 25.0, 1e-12);
    }
  }
}

TEST(PlaneContactNodes, UprightOrRockingBlockPressesWithItsBaseSharesOnly) {
  const Clump box(ConvexShape::box({0.25, 0.25, 0.5}));
  const PlaneContactNodes nodes =
      make_plane_contact_nodes(box, Vector3d(0, 0, 0.5), 100.0, layout(NodeLayout::kVertices));
  std::vector<int> acting(3);
  // Upright, and rocking by 0.2 rad about y (the side face then points down
  // by sin 0.2 only, the base by cos 0.2).
  for (double tilt : {0.0, 0.2}) {
    const Vector3d up = Eigen::AngleAxisd(tilt, Vector3d::UnitY()).inverse() * Vector3d::UnitZ();
    for (std::size_t k = 0; k < 4; ++k) {
      ASSERT_EQ(nodes.acting_shares(k, up, acting.data()), 1);
      EXPECT_EQ(acting[0], nodes.first_share[k]);
      EXPECT_DOUBLE_EQ(nodes.area[acting[0]], 0.0625);
    }
  }
}

TEST(PlaneContactNodes, EveryFaceCarriesItsAreaAndFirstMomentWhenLyingOnIt) {
  // A block and an octagonal drum, surface grids: lying on any face f (world
  // up = -n_f), the acting shares of f's points sum to f's area and first
  // moment to round-off, as a base-only node set does on the base.
  const Vector3d com(0, 0, 0.3);
  for (const ConvexShape& shape : {ConvexShape::box({0.2, 0.3, 0.5}), ConvexShape::prism(0.45, 8, 0.6)}) {
    const Clump body(shape);
    const PlaneContactNodes nodes = make_plane_contact_nodes(body, com, 50.0, layout(NodeLayout::kSurface, 4));
    for (const freestand::ShapeFace& face : shape.faces()) {
      const Acting a = acting_on_lowest_plane(nodes, -face.normal);
      EXPECT_NEAR(a.area, face.area, 1e-12 * face.area);
      EXPECT_NEAR((a.moment - face.area * (face.centroid - com)).norm(), 0.0, 1e-12);
    }
  }
}

TEST(PlaneContactNodes, CoplanarBaseFacesOfAClumpActTogether) {
  // Two boxes side by side: the points on their shared bottom edge belong to
  // both base faces, and both shares act.
  freestand::ClumpPiece left{ConvexShape::box({0.25, 0.3, 0.5})}, right{ConvexShape::box({0.25, 0.3, 0.5})};
  left.offset = {-0.25, 0, 0};
  right.offset = {0.25, 0, 0};
  const Clump body({left, right});
  const PlaneContactNodes nodes =
      make_plane_contact_nodes(body, Vector3d(0, 0, 0.5), 300.0, layout(NodeLayout::kSurface, 2));
  const Acting a = acting_on_lowest_plane(nodes, Vector3d::UnitZ());
  EXPECT_NEAR(a.area, 1.0 * 0.6, 1e-12);
  EXPECT_NEAR(a.moment.head<2>().norm(), 0.0, 1e-12);
  EXPECT_EQ(a.points, 15);  // a 5 x 3 grid over the whole 1.0 x 0.6 base
}
