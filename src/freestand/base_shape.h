#ifndef FREESTAND_BASE_SHAPE_H
#define FREESTAND_BASE_SHAPE_H

// A base that is not the ideal flat polygon of the body's shape: corners
// short of the base plane (an uneven or chipped base that rests on three
// corners) and edges rounded or crushed (a narrower effective base). Only the
// contact nodes on the base move; the shape, and with it the mass, centre of
// mass and inertia, stay as stated. docs/fix_rigid_convex.md, "Base".

#include <Eigen/Core>
#include <vector>

#include "freestand/shape_clump.h"

namespace freestand {

struct CornerGap {
  Eigen::Vector2d direction;  // picks the base corner farthest along (x, y) of the body frame
  double gap = 0.0;           // m the corner is short of the base plane (> 0), or proud of it (< 0)
};

struct BaseShape {
  double edge_inset = 0.0;              // m: base nodes moved inward from every base edge
  std::vector<CornerGap> corner_gaps;   // corners off the base plane
  bool flat() const { return edge_inset == 0.0 && corner_gaps.empty(); }
};

// Where the points of a body's base faces go. A point p of a base face with
// corners v_i is written as p = sum w_i v_i (linear along the edges, mean
// value coordinates inside: exact for every affine map) and goes to
//   p' = sum w_i v'_i + (sum w_i g_i) u,
// v'_i the corners of the face inset by edge_inset (each edge moved inward
// along the face), g_i the corner gaps, u the unit normal into the body. So
// a base whose gaps lie in a plane becomes that plane, and an inset base is
// the narrower polygon with every node at the same place relative to it.
class BaseMap {
 public:
  // Throws InputError for an inset with more than one base face or too large
  // for the base, or a corner direction that does not single out a corner.
  BaseMap(const Clump& body, const BaseShape& shape);
  // p moved if it lies on a base face (boundary included), else p.
  Eigen::Vector3d operator()(const Eigen::Vector3d& p) const;

 private:
  struct Face {
    Eigen::Vector3d normal;               // outward (down)
    double offset;                        // normal . p on the face
    std::vector<Eigen::Vector3d> corner;  // counter-clockwise about the normal
    std::vector<Eigen::Vector3d> target;  // where each corner goes
  };
  std::vector<Face> faces_;
  double tolerance_ = 0.0;  // m: on a face within this
};

// Weights w_i >= 0, sum 1, with sum w_i poly_i = x, of a point x of a convex
// polygon (corners counter-clockwise about n): 1 at a corner, linear along
// an edge, mean value coordinates (Floater 2003) inside. `tolerance` (m):
// how near a corner or edge counts as on it.
void polygon_weights(const std::vector<Eigen::Vector3d>& poly, const Eigen::Vector3d& x,
                     const Eigen::Vector3d& n, double tolerance, std::vector<double>* w);

}  // namespace freestand

#endif
