#ifndef FREESTAND_CONVEX_SHAPE_H
#define FREESTAND_CONVEX_SHAPE_H

// A convex polyhedron in a body frame: the geometry kernel behind
// `fix rigid/convex` and `pair_style convex`. docs/shapes.md is the precise
// statement of frames, parameters, formulas and tolerances.
//
// Body frame (../shared/recording-format.md): origin at the centre of the
// base face, z up, metres. A shape holds
//   - its vertices (the corners of the polytope, nothing else),
//   - its faces: outward unit normal n, offset d (points with n.x <= d are on
//     the inner side), vertex loop counter-clockwise seen from outside, area
//     and centroid; coplanar facets are one face (a box has 6 faces),
//   - its edges, each with the two faces that meet there.
// Shapes are immutable once built; every query is const, allocation-free and
// safe to call from several threads.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace freestand {

// One planar face of a convex polyhedron.
struct ShapeFace {
  Eigen::Vector3d normal;   // outward unit normal
  double offset = 0.0;      // n.x <= offset on the inner side (m)
  std::vector<int> loop;    // vertex indices, counter-clockwise seen from outside
  double area = 0.0;        // m^2
  Eigen::Vector3d centroid; // area centroid (m)
};

// One edge: vertex v0 -> v1 runs counter-clockwise in face `left`'s loop and
// v1 -> v0 in face `right`'s loop.
struct ShapeEdge {
  int v0 = -1, v1 = -1;
  int left = -1, right = -1;
};

// Volume, mass, centre of mass and inertia of a body of uniform density.
struct MassProperties {
  double volume = 0.0;                                 // m^3
  double mass = 0.0;                                   // kg
  Eigen::Vector3d com = Eigen::Vector3d::Zero();       // centre of mass, body frame (m)
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();   // about the COM, body frame (kg m^2)
};

// max over faces of n.x - d, and the first face achieving it.
struct PlaneDistance {
  double value = 0.0;  // m; <= 0 inside (then it is minus the exact depth)
  int face = -1;
};

// Which part of the surface a closest point lies on.
enum class SurfaceFeature { kFace, kEdge, kVertex };

// Signed distance of a point to the surface, with what produced it.
struct SurfaceDistance {
  double distance = 0.0;        // m; < 0 inside, 0 on the surface, > 0 outside
  Eigen::Vector3d normal;       // unit; outward normal of `face` inside, (x - point)/distance outside
  Eigen::Vector3d point;        // closest point on the surface (m)
  int face = -1;                // least-penetration face (inside) / a face holding `point` (outside)
  SurfaceFeature feature = SurfaceFeature::kFace;
  int feature_index = -1;       // index of that face, edge or vertex
};

class ConvexShape {
 public:
  // Rectangular box, half extents (a, b, c) > 0: x in [-a, a], y in [-b, b],
  // z in [0, 2c]. Faces: 0 base (-z), 1 top (+z), 2 -y, 3 +x, 4 +y, 5 -x.
  static ConvexShape box(const Eigen::Vector3d& half_extents);

  // Right prism on a regular polygon: circumradius r > 0, sides >= 3, height
  // h > 0, z in [0, h]. Base vertex k is at angle (2k + 1) pi / sides from +x,
  // so the side face between the last and the first vertex faces +x (a
  // 4-sided prism is the box with half extents r/sqrt(2), r/sqrt(2), h/2).
  // Vertices 0..n-1 base ring, n..2n-1 top ring; faces 0 base, 1 top, 2 + k
  // the side from vertex k to k + 1 (outward normal at angle 2 (k + 1) pi / n).
  static ConvexShape prism(double radius, int sides, double height);

  // Convex hull (Qhull) of `points`. Rejects non-finite coordinates, fewer
  // than 4 points, duplicates (closer than tolerance()), collinear or coplanar
  // sets, with an InputError naming the offending points. Points that are not
  // corners of the hull (inside, or on a face or edge) are dropped and listed
  // in notes(). `what` prefixes messages, e.g. "body 'statue': convex".
  static ConvexShape hull(const std::vector<Eigen::Vector3d>& points,
                          const std::string& what = "convex");

  // This shape moved rigidly: x -> rotation * x + offset. `rotation` must be
  // a proper rotation (orthonormal, det +1) to 1e-9, else InputError.
  ConvexShape transformed(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& offset) const;

  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  const std::vector<ShapeFace>& faces() const { return faces_; }
  const std::vector<ShapeEdge>& edges() const { return edges_; }
  // For hull(): the index in the input list of each vertex; for box/prism,
  // 0..n-1.
  const std::vector<int>& source_index() const { return source_index_; }
  // Human-readable remarks made while building (dropped points).
  const std::vector<std::string>& notes() const { return notes_; }
  // Geometric tolerance (m): 1e-9 times the bounding-box diagonal.
  double tolerance() const { return tolerance_; }

  double volume() const { return mass_.volume; }
  // Mass properties at `density` (kg/m^3 > 0), exact polyhedral integration.
  MassProperties mass_properties(double density) const;

  Eigen::AlignedBox3d bounding_box() const { return box_; }
  // Largest distance from `centre` to a vertex: the radius of the smallest
  // sphere about `centre` (e.g. the COM) that holds the shape.
  double bounding_radius(const Eigen::Vector3d& centre) const;

  // max_f (n_f.x - d_f) and the face achieving it. Inside (value <= 0) this is
  // exactly minus the distance to the surface and that face is the face of
  // least penetration. Outside it is a lower bound on the distance, exact
  // when the closest point lies inside a face. Cost: one dot product per face.
  PlaneDistance max_plane_distance(const Eigen::Vector3d& x) const;

  // Exact signed Euclidean distance to the surface. Inside it equals
  // max_plane_distance(); outside it is the distance to the closest surface
  // point, found on the faces whose plane separates x (costs a walk over
  // their loops; use it in a contact skin only).
  SurfaceDistance signed_distance(const Eigen::Vector3d& x) const;

  // Internal constructor for faces given as loops (counter-clockwise seen from
  // outside). Computes planes (Newell normals unless `normals` gives one per
  // face), areas, centroids, edges and checks the polytope is closed and
  // convex; used by box, prism, hull and transformed.
  static ConvexShape from_loops(std::vector<Eigen::Vector3d> vertices,
                                std::vector<std::vector<int>> loops,
                                const std::string& what,
                                const std::vector<Eigen::Vector3d>* normals = nullptr);

 private:
  ConvexShape() = default;
  void finish(const std::string& what, const std::vector<Eigen::Vector3d>* normals);

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<ShapeFace> faces_;
  std::vector<ShapeEdge> edges_;
  std::vector<int> source_index_;
  std::vector<std::string> notes_;
  double tolerance_ = 0.0;
  Eigen::AlignedBox3d box_;
  MassProperties mass_;  // at unit density

  // Flat copies for the per-step queries.
  std::vector<Eigen::Vector3d> normals_;
  std::vector<double> offsets_;
  std::vector<int> loop_begin_;  // faces_.size() + 1 entries into loop_vertex_
  std::vector<int> loop_vertex_;
  std::vector<int> loop_edge_;   // edge from loop_vertex_[i] to the next one
};

// Exact volume integrals of a closed polyhedron with planar faces given as
// loops counter-clockwise seen from outside, at unit density.
MassProperties polyhedron_mass_properties(const std::vector<Eigen::Vector3d>& vertices,
                                          const std::vector<std::vector<int>>& loops);

}  // namespace freestand

#endif
