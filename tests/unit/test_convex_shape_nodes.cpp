// Contact nodes: on every face and for every resolution and layout the
// tributary areas must sum to the face area and their first moment must equal
// area times centroid, so a uniformly pressed face gives the exact resultant
// and moment.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "freestand/contact_nodes.h"
#include "freestand/convex_shape.h"
#include "freestand/input_error.h"
#include "freestand/shape_clump.h"

using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using freestand::Clump;
using freestand::ClumpPiece;
using freestand::ContactNode;
using freestand::ConvexShape;
using freestand::FaceRef;
using freestand::NodeKind;
using freestand::NodeLayout;
using freestand::NodeOptions;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A face's node areas are sums of up to ~10^4 positive terms, each exact to
// 1e-16 relative: 1e-12 relative is round-off, while any lumping that is not
// exact (equal shares on a non-parallelogram cell, a dropped node, a
// double-counted edge) is off by 1e-3 or more.
constexpr double kAreaTol = 1e-12;

struct Named {
  std::string name;
  Clump body;
};

// A unit-ish cube with one corner cut off: triangle, three pentagons, three
// squares, so every grid (triangle, parallelogram, rings) is exercised.
ConvexShape cut_cube() {
  std::vector<Vector3d> p;
  for (int i = 0; i < 8; ++i)
    if (i != 7) p.emplace_back((i & 1) ? 0.5 : -0.5, (i & 2) ? 0.5 : -0.5, (i & 4) ? 1.0 : 0.0);
  p.emplace_back(0.1, 0.5, 1.0);
  p.emplace_back(0.5, 0.2, 1.0);
  p.emplace_back(0.5, 0.5, 0.6);
  return ConvexShape::hull(p);
}

std::vector<Named> shapes() {
  std::vector<Named> out;
  out.push_back({"box", Clump(ConvexShape::box(Vector3d(0.5, 0.3, 1.0)))});
  for (int n : {3, 5, 8, 24}) out.push_back({"prism " + std::to_string(n), Clump(ConvexShape::prism(0.4, n, 0.9))});
  out.push_back({"tetrahedron", Clump(ConvexShape::hull({{0, 0, 0}, {0.7, 0, 0}, {0.1, 0.5, 0}, {0.2, 0.1, 0.8}}))});
  out.push_back({"cut cube", Clump(cut_cube())});
  // A frustum: trapezoid sides (quadrilaterals that are not parallelograms).
  out.push_back({"frustum", Clump(ConvexShape::hull({{-0.5, -0.4, 0}, {0.5, -0.4, 0}, {0.5, 0.4, 0}, {-0.5, 0.4, 0},
                                                     {-0.2, -0.1, 0.6}, {0.3, -0.1, 0.6}, {0.3, 0.2, 0.6},
                                                     {-0.2, 0.2, 0.6}}))});
  std::mt19937 rng(2);
  std::normal_distribution<double> g(0.0, 0.3);
  std::vector<Vector3d> p;
  for (int i = 0; i < 25; ++i) p.emplace_back(g(rng), g(rng), g(rng));
  out.push_back({"random hull", Clump(ConvexShape::hull(p))});
  ClumpPiece a{ConvexShape::prism(0.3, 6, 0.5)};
  ClumpPiece b{ConvexShape::box(Vector3d(0.2, 0.1, 0.3))};
  b.orientation = Quaterniond(AngleAxisd(0.4, Vector3d(1, 1, 0).normalized()));
  b.offset = Vector3d(0.1, 0.05, 0.7);
  out.push_back({"tilted clump", Clump({a, b})});
  return out;
}

std::vector<NodeOptions> resolutions() {
  std::vector<NodeOptions> out;
  for (NodeLayout layout : {NodeLayout::kSurface, NodeLayout::kBoundary, NodeLayout::kVertices}) {
    for (int n : {1, 2, 3, 7}) {
      NodeOptions o;
      o.per_edge = n;
      o.layout = layout;
      out.push_back(o);
    }
    for (double h : {0.25, 0.1, 0.037}) {
      NodeOptions o;
      o.spacing = h;
      o.layout = layout;
      out.push_back(o);
    }
  }
  return out;
}

std::string describe(const NodeOptions& o) {
  const char* layout = o.layout == NodeLayout::kSurface ? "surface" : o.layout == NodeLayout::kBoundary ? "boundary"
                                                                                                          : "vertices";
  return o.spacing > 0 ? "spacing " + std::to_string(o.spacing) + " " + layout
                       : "per_edge " + std::to_string(o.per_edge) + " " + layout;
}

}  // namespace

TEST(Nodes, AreaAndFirstMomentExactOnEveryFaceAtEveryResolution) {
  double worst_area = 0.0, worst_moment = 0.0;
  for (const Named& s : shapes()) {
    for (const NodeOptions& o : resolutions()) {
      const std::vector<ContactNode> nodes = freestand::make_contact_nodes(s.body, o);
      for (size_t pi = 0; pi < s.body.pieces().size(); ++pi) {
        const ConvexShape& piece = s.body.pieces()[pi];
        for (size_t f = 0; f < piece.faces().size(); ++f) {
          const auto& face = piece.faces()[f];
          const std::string where = s.name + ", " + describe(o) + ", piece " + std::to_string(pi) + " face " +
                                    std::to_string(f);
          double area = 0.0;
          Vector3d moment = Vector3d::Zero();
          int count = 0, corners = 0;
          for (const ContactNode& n : nodes) {
            if (n.piece != static_cast<int>(pi) || n.face != static_cast<int>(f)) continue;
            ++count;
            area += n.area;
            moment += n.area * n.position;
            EXPECT_GT(n.area, 0.0) << where;
            EXPECT_EQ(n.normal, face.normal) << where;
            EXPECT_NEAR(face.normal.dot(n.position), face.offset, 1e-12) << where;  // on the face plane
            EXPECT_LE(piece.max_plane_distance(n.position).value, 1e-12) << where;  // inside the face
            if (n.kind == NodeKind::kVertex) {
              ++corners;
              ASSERT_GE(n.vertex, 0) << where;
              EXPECT_EQ(n.position, piece.vertices()[n.vertex]) << where;
            } else {
              EXPECT_EQ(n.vertex, -1) << where;
            }
            if (o.layout != NodeLayout::kSurface) EXPECT_NE(n.kind, NodeKind::kInterior) << where;
            if (o.layout == NodeLayout::kVertices) EXPECT_EQ(n.kind, NodeKind::kVertex) << where;
          }
          EXPECT_EQ(corners, static_cast<int>(face.loop.size())) << where;
          if (o.layout == NodeLayout::kVertices) EXPECT_EQ(count, static_cast<int>(face.loop.size())) << where;
          const double area_err = std::abs(area - face.area) / face.area;
          const double size = std::sqrt(face.area) + face.centroid.norm();
          const double moment_err = (moment - face.area * face.centroid).norm() / (face.area * size);
          EXPECT_LE(area_err, kAreaTol) << where;
          EXPECT_LE(moment_err, kAreaTol) << where;
          worst_area = std::max(worst_area, area_err);
          worst_moment = std::max(worst_moment, moment_err);
        }
      }
    }
  }
  std::printf("[measured] nodes: worst relative area error %.1e, worst relative first-moment error %.1e\n", worst_area,
              worst_moment);
}

TEST(Nodes, FaceCentroidsOfBoxAndPrismAreTheClosedForms) {
  // The reference centroids used above, checked against closed forms.
  const ConvexShape b = ConvexShape::box(Vector3d(0.5, 0.3, 1.0));
  const std::vector<Vector3d> box_c = {{0, 0, 0}, {0, 0, 2}, {0, -0.3, 1}, {0.5, 0, 1}, {0, 0.3, 1}, {-0.5, 0, 1}};
  for (int f = 0; f < 6; ++f) EXPECT_LE((b.faces()[f].centroid - box_c[f]).norm(), 1e-15) << f;
  const int n = 7;
  const double r = 0.4, h = 0.9;
  const ConvexShape p = ConvexShape::prism(r, n, h);
  EXPECT_LE(p.faces()[0].centroid.norm(), 1e-15);
  EXPECT_LE((p.faces()[1].centroid - Vector3d(0, 0, h)).norm(), 1e-15);
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * (k + 1) * kPi / n;
    const double apothem = r * std::cos(kPi / n);
    EXPECT_LE((p.faces()[2 + k].centroid - Vector3d(apothem * std::cos(t), apothem * std::sin(t), h / 2)).norm(),
              1e-15)
        << k;
  }
}

TEST(Nodes, UniformPressureGivesExactResultantAndMoment) {
  // Pressure q on one face pushes along -n: resultant -q A n, moment about o
  // (c - o) x (-q A n). Summed over nodes it must be the same.
  const Clump body(cut_cube());
  const double q = 2.0e5;
  const Vector3d o(0.3, -0.2, 0.1);
  for (int n : {1, 4, 9}) {
    NodeOptions opt;
    opt.per_edge = n;
    const auto nodes = freestand::make_contact_nodes(body, opt);
    for (size_t f = 0; f < body.pieces()[0].faces().size(); ++f) {
      const auto& face = body.pieces()[0].faces()[f];
      Vector3d force = Vector3d::Zero(), moment = Vector3d::Zero();
      for (const ContactNode& node : nodes)
        if (node.face == static_cast<int>(f)) {
          force += -q * node.area * node.normal;
          moment += (node.position - o).cross(-q * node.area * node.normal);
        }
      const Vector3d f_ref = -q * face.area * face.normal;
      const Vector3d m_ref = (face.centroid - o).cross(f_ref);
      EXPECT_LE((force - f_ref).norm(), 1e-12 * f_ref.norm()) << n << " " << f;
      EXPECT_LE((moment - m_ref).norm(), 1e-12 * f_ref.norm()) << n << " " << f;
    }
  }
}

TEST(Nodes, BoxFaceGridCountsAndShares) {
  const Clump body(ConvexShape::box(Vector3d(0.5, 0.3, 1.0)));  // top face 1.0 x 0.6
  NodeOptions o;
  o.per_edge = 2;
  o.faces = {{0, 1}};
  auto nodes = freestand::make_contact_nodes(body, o);
  ASSERT_EQ(nodes.size(), 9u);
  const double a = 0.6;
  int corners = 0, edges = 0, centres = 0;
  for (const ContactNode& n : nodes) {
    if (n.kind == NodeKind::kVertex) {
      EXPECT_NEAR(n.area, a / 16, 1e-15);
      ++corners;
    }
    if (n.kind == NodeKind::kEdge) {
      EXPECT_NEAR(n.area, a / 8, 1e-15);
      ++edges;
    }
    if (n.kind == NodeKind::kInterior) {
      EXPECT_NEAR(n.area, a / 4, 1e-15);
      EXPECT_LE((n.position - Vector3d(0, 0, 2)).norm(), 1e-15);
      ++centres;
    }
  }
  EXPECT_EQ(corners, 4);
  EXPECT_EQ(edges, 4);
  EXPECT_EQ(centres, 1);
  // Spacing 0.1 m: 10 x 6 cells, 11 x 7 nodes, spaced exactly 0.1 m.
  o.per_edge = 1;
  o.spacing = 0.1;
  nodes = freestand::make_contact_nodes(body, o);
  EXPECT_EQ(nodes.size(), 77u);
  // Spacing 0.15 m: ceil(1.0/0.15) = 7 by ceil(0.6/0.15) = 4 cells.
  o.spacing = 0.15;
  EXPECT_EQ(freestand::make_contact_nodes(body, o).size(), 8u * 5u);
  // Vertices only: a quarter of the face at each corner (Housner's block).
  o.layout = NodeLayout::kVertices;
  nodes = freestand::make_contact_nodes(body, o);
  ASSERT_EQ(nodes.size(), 4u);
  for (const ContactNode& n : nodes) EXPECT_NEAR(n.area, a / 4, 1e-15);
}

TEST(Nodes, TriangleAndPolygonGridCounts) {
  // Triangle, n per edge: (n + 1)(n + 2)/2 nodes. Polygon with m corners, n
  // rings: 1 + m n (n + 1)/2 nodes.
  const Clump tet(ConvexShape::hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}));
  const Clump drum(ConvexShape::prism(0.5, 12, 0.4));
  for (int n : {1, 2, 5}) {
    NodeOptions o;
    o.per_edge = n;
    o.faces = {{0, 0}};
    EXPECT_EQ(freestand::make_contact_nodes(tet, o).size(), static_cast<size_t>((n + 1) * (n + 2) / 2));
    EXPECT_EQ(freestand::make_contact_nodes(drum, o).size(), static_cast<size_t>(1 + 12 * n * (n + 1) / 2));
    o.layout = NodeLayout::kBoundary;
    EXPECT_EQ(freestand::make_contact_nodes(drum, o).size(), static_cast<size_t>(12 * n));
  }
}

TEST(Nodes, RegularPolygonVerticesShareTheFaceEqually) {
  const ConvexShape drum = ConvexShape::prism(0.5, 16, 0.4);
  NodeOptions o;
  o.layout = NodeLayout::kVertices;
  o.faces = {{0, 0}, {0, 1}};
  const auto nodes = freestand::make_contact_nodes(drum, o);
  ASSERT_EQ(nodes.size(), 32u);
  for (const ContactNode& n : nodes) EXPECT_NEAR(n.area, drum.faces()[0].area / 16, 1e-15);
}

TEST(Nodes, SpacingBoundsTheDistanceBetweenNeighbours) {
  // Every node of a spacing-h surface grid has another node of its face
  // within h (the grid is no coarser than asked), except on slivers
  // (area / diameter < h/2), which get their corners only.
  for (const Named& s : shapes()) {
    NodeOptions o;
    o.spacing = 0.05;
    const auto nodes = freestand::make_contact_nodes(s.body, o);
    for (size_t i = 0; i < nodes.size(); ++i) {
      const ConvexShape& piece = s.body.pieces()[nodes[i].piece];
      const auto& face = piece.faces()[nodes[i].face];
      double diameter = 0;
      for (int a : face.loop)
        for (int b : face.loop) diameter = std::max(diameter, (piece.vertices()[a] - piece.vertices()[b]).norm());
      if (face.area / diameter < 0.025) continue;
      double nearest = 1e300;
      for (size_t j = 0; j < nodes.size(); ++j)
        if (j != i && nodes[j].piece == nodes[i].piece && nodes[j].face == nodes[i].face)
          nearest = std::min(nearest, (nodes[j].position - nodes[i].position).norm());
      EXPECT_LE(nearest, 0.05 * (1 + 1e-9)) << s.name << " node " << i;
    }
  }
}

TEST(Nodes, SliverFacesGetVertexNodesOnly) {
  // Face 0-1-2 is 1 m long and 2 mm wide: at spacing 5 cm its lattice would
  // hold 231 nodes on 1e-3 m^2; it gets its 3 corners, still exact.
  const ConvexShape s = ConvexShape::hull({{0, 0, 0}, {1, 0, 0}, {0.5, 0.002, 0}, {0.5, 0.5, 0.5}});
  NodeOptions o;
  o.spacing = 0.05;
  const auto nodes = freestand::make_contact_nodes(s, o);
  int sliver = -1;
  for (size_t f = 0; f < s.faces().size(); ++f)
    if (s.faces()[f].area < 0.01) sliver = static_cast<int>(f);
  ASSERT_GE(sliver, 0);
  double area = 0;
  Vector3d moment = Vector3d::Zero();
  int count = 0;
  for (const ContactNode& n : nodes)
    if (n.face == sliver) {
      ++count;
      area += n.area;
      moment += n.area * n.position;
      EXPECT_EQ(n.kind, NodeKind::kVertex);
    }
  EXPECT_EQ(count, 3);
  const auto& face = s.faces()[sliver];
  EXPECT_NEAR(area, face.area, 1e-12 * face.area);
  EXPECT_LE((moment - face.area * face.centroid).norm(), 1e-12 * face.area);
  EXPECT_GT(nodes.size(), 3u * 50u);  // the other faces are gridded
}

TEST(Nodes, BaseOnlySelection) {
  const Clump body(ConvexShape::prism(0.45, 20, 1.0));
  NodeOptions o;
  o.spacing = 0.05;
  o.faces = body.base_faces();
  ASSERT_EQ(o.faces.size(), 1u);
  EXPECT_EQ(o.faces[0].face, 0);
  const auto nodes = freestand::make_contact_nodes(body, o);
  double area = 0;
  for (const ContactNode& n : nodes) {
    EXPECT_EQ(n.face, 0);
    EXPECT_EQ(n.position.z(), 0.0);
    area += n.area;
  }
  EXPECT_NEAR(area, body.pieces()[0].faces()[0].area, 1e-14);
}

// Refining only the bearing faces (base and top) keeps every face's area and first moment
// exact (the corners-only faces are grids of one cell) and cuts the node count: a box at 8
// segments per edge has 6 x 81 nodes on all faces, 2 x 81 + 4 x 4 on its bearing faces.
TEST(Nodes, RefinedFacesOnlyKeepEveryFaceExact) {
  const Clump body(ConvexShape::box(Vector3d(0.2, 0.3, 0.8)));
  NodeOptions o;
  o.per_edge = 8;
  o.refined = body.bearing_faces();
  ASSERT_EQ(o.refined.size(), 2u);
  const auto nodes = freestand::make_contact_nodes(body, o);
  EXPECT_EQ(nodes.size(), 2u * 81u + 4u * 4u);
  const auto& faces = body.pieces()[0].faces();
  for (size_t f = 0; f < faces.size(); ++f) {
    double area = 0;
    Vector3d moment = Vector3d::Zero();
    for (const ContactNode& n : nodes)
      if (n.face == static_cast<int>(f)) {
        area += n.area;
        moment += n.area * n.position;
      }
    EXPECT_NEAR(area, faces[f].area, 1e-12);
    EXPECT_LE((moment - faces[f].area * faces[f].centroid).norm(), 1e-12);
  }
  o.refined = {{0, 9}};
  EXPECT_THROW(freestand::make_contact_nodes(body, o), freestand::InputError);
}

TEST(Nodes, CountsForTypicalBodies) {
  // The Duzce block (1 x 1 x 3 m) and a 20-sided column drum (r 0.5 m, 0.6 m
  // high). Box faces are n_u x n_v grids: at h = 0.1, 11 x 11 on the base and
  // 11 x 31 on each side.
  const Clump block(ConvexShape::box(Vector3d(0.5, 0.5, 1.5)));
  const Clump drum(ConvexShape::prism(0.5, 20, 0.6));
  auto count = [](const Clump& body, double h, bool base_only, NodeLayout layout) {
    NodeOptions o;
    o.spacing = h;
    o.layout = layout;
    if (base_only) o.faces = body.base_faces();
    return freestand::make_contact_nodes(body, o).size();
  };
  EXPECT_EQ(count(block, 0.1, false, NodeLayout::kSurface), 2u * 121u + 4u * 341u);
  EXPECT_EQ(count(block, 0.1, true, NodeLayout::kSurface), 121u);
  EXPECT_EQ(count(block, 0.1, true, NodeLayout::kBoundary), 40u);
  EXPECT_EQ(count(block, 0.1, true, NodeLayout::kVertices), 4u);
  for (const auto& [name, body] : {std::pair<const char*, const Clump&>{"block 1x1x3", block},
                                   std::pair<const char*, const Clump&>{"drum r0.5 20 sides", drum}})
    for (double h : {0.1, 0.05, 0.02})
      std::printf("[measured] nodes, %s, h = %.2f m: surface %zu (base only %zu), boundary %zu (base %zu), "
                  "vertices %zu (base %zu)\n",
                  name, h, count(body, h, false, NodeLayout::kSurface), count(body, h, true, NodeLayout::kSurface),
                  count(body, h, false, NodeLayout::kBoundary), count(body, h, true, NodeLayout::kBoundary),
                  count(body, h, false, NodeLayout::kVertices), count(body, h, true, NodeLayout::kVertices));
}

TEST(Nodes, BadOptionsAreRejected) {
  const Clump body(ConvexShape::box(Vector3d(1, 1, 1)));
  auto message = [&](const NodeOptions& o) {
    try {
      freestand::make_contact_nodes(body, o);
    } catch (const freestand::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no InputError)");
  };
  NodeOptions o;
  o.per_edge = 0;
  EXPECT_EQ(message(o), "contact nodes: per_edge must be at least 1, got 0");
  o = NodeOptions();
  o.spacing = -0.1;
  EXPECT_EQ(message(o), "contact nodes: spacing must be >= 0 and finite, got -0.1");
  o = NodeOptions();
  o.faces = {{0, 6}};
  EXPECT_EQ(message(o), "contact nodes: no face 6 on piece 0");
  o.faces = {{0, 1}, {0, 1}};
  EXPECT_EQ(message(o), "contact nodes: face 1 of piece 0 is selected twice");
}
