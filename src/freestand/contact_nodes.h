#ifndef FREESTAND_CONTACT_NODES_H
#define FREESTAND_CONTACT_NODES_H

// Contact nodes: points on the faces of a body, each carrying a tributary
// area, like the surface nodes of a solid mesh. The penalty contact of
// `pair_style convex` presses each node of one body against the faces of the
// other body (or the table plane) with a force proportional to its area.
//
// Exactness: on every face the node areas sum to the face area and their
// first moment sum A_i x_i equals area * centroid, to round-off, for every
// resolution and layout. A uniformly pressed face therefore gives the exact
// resultant and moment whatever the refinement. docs/shapes.md describes the
// grids and how vertices get their share.

#include <Eigen/Core>
#include <vector>

#include "freestand/base_shape.h"
#include "freestand/convex_shape.h"
#include "freestand/shape_clump.h"

namespace freestand {

enum class NodeLayout {
  kSurface,   // grid over each face: vertices, edge points and interior points
  kBoundary,  // vertices and edge points only; interior area moved onto them
  kVertices,  // vertices only (Housner-type corner contact); ignores the resolution
};

struct NodeOptions {
  double spacing = 0.0;  // target node spacing h (m); > 0 takes precedence over per_edge
  int per_edge = 1;      // with spacing == 0: every face edge is cut into this many segments
  NodeLayout layout = NodeLayout::kSurface;
  std::vector<FaceRef> faces;  // faces that get nodes; empty: every face not kCovered
  std::vector<FaceRef> refined;  // faces cut at spacing/per_edge; empty: all. The others get their
                                 // corners only (per_edge 1), enough for a toppled body to land on
  BaseShape base;              // base not flat: its nodes move (the exactness below is then
                               // that of the moved base, base_shape.h)
};

enum class NodeKind { kVertex, kEdge, kInterior };

struct ContactNode {
  Eigen::Vector3d position;  // body frame (m)
  Eigen::Vector3d normal;    // outward unit normal of the node's face
  double area = 0.0;         // tributary area on that face (m^2), > 0
  int piece = 0;             // clump piece
  int face = 0;              // face of that piece
  int vertex = -1;           // the piece's vertex index when the node is at a vertex, else -1
  NodeKind kind = NodeKind::kInterior;
};

// Nodes of one planar convex polygon (corners counter-clockwise about
// `normal`), before they are attached to a body. `corner` is the index in
// `loop` of a node sitting on a corner, else -1.
struct PolygonNodes {
  std::vector<Eigen::Vector3d> position;
  std::vector<double> area;
  std::vector<int> corner;
  std::vector<NodeKind> kind;
};
PolygonNodes polygon_nodes(const std::vector<Eigen::Vector3d>& loop, const Eigen::Vector3d& normal,
                           const NodeOptions& options);

// Every selected face's nodes; a node on an edge or vertex appears once for
// each selected face holding it (with that face's normal and share).
// Throws InputError for a bad resolution or face selection.
std::vector<ContactNode> make_contact_nodes(const Clump& body, const NodeOptions& options);
std::vector<ContactNode> make_contact_nodes(const ConvexShape& shape, const NodeOptions& options);

}  // namespace freestand

#endif
