#ifndef FREESTAND_SHAPE_CLUMP_H
#define FREESTAND_SHAPE_CLUMP_H

// A clump: several convex pieces rigidly joined into one body (an eccentric
// statue on its plinth, an L-shaped cabinet). Each piece is a ConvexShape in
// its own frame, placed in the body frame by a rotation and an offset. A
// single convex body is a clump of one piece, so the contact code only needs
// this type. docs/shapes.md states the conventions.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "freestand/convex_shape.h"

namespace freestand {

// One piece as the user describes it.
struct ClumpPiece {
  ConvexShape shape;                                                 // in the piece's own frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();   // piece frame -> body frame
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();                  // piece-frame origin in the body frame (m)
};

// A face of a clump.
struct FaceRef {
  int piece = 0;
  int face = 0;
  bool operator==(const FaceRef& o) const { return piece == o.piece && face == o.face; }
};

// How much of a face is glued against coplanar faces of other pieces.
enum class FaceCover {
  kExposed,        // nothing against it
  kPartlyCovered,  // part of it is against another piece
  kCovered,        // all of it is against other pieces: inside the body
};

// Signed distance to a clump, with the piece that produced it.
struct ClumpDistance {
  SurfaceDistance surface;  // in the body frame; surface.face is a face of `piece`
  int piece = -1;
};

class Clump {
 public:
  // A single convex body.
  explicit Clump(const ConvexShape& shape);

  // Pieces must not overlap (their volumes would be counted twice): pieces
  // whose interiors intersect by more than the tolerance are rejected with an
  // InputError. Touching pieces (a shared face) are fine; faces lying
  // against other pieces are classified by cover().
  explicit Clump(const std::vector<ClumpPiece>& pieces, const std::string& what = "clump");

  // The pieces in the body frame.
  const std::vector<ConvexShape>& pieces() const { return pieces_; }
  FaceCover cover(const FaceRef& f) const { return cover_[f.piece][f.face]; }
  // Fraction of the face's area lying against other pieces, in [0, 1].
  double covered_fraction(const FaceRef& f) const { return covered_fraction_[f.piece][f.face]; }
  const std::vector<std::string>& notes() const { return notes_; }
  double tolerance() const { return tolerance_; }

  double volume() const;
  MassProperties mass_properties(double density) const;
  // One density per piece (kg/m^3), e.g. a hollow bronze on a stone plinth.
  MassProperties mass_properties(const std::vector<double>& densities) const;

  Eigen::AlignedBox3d bounding_box() const;
  double bounding_radius(const Eigen::Vector3d& centre) const;

  // Faces whose outward normal is -z (within 1e-9 rad) and that lie in the
  // lowest plane z = min z of the clump: the faces a body stands on.
  std::vector<FaceRef> base_faces() const;
  // The base faces and the faces whose outward normal is +z in the highest
  // plane: where a body bears on what supports it and what it supports.
  std::vector<FaceRef> bearing_faces() const;

  // Signed distance to the union of the pieces. Outside every piece: the
  // exact Euclidean distance (minimum over pieces). Inside a piece: the
  // maximum of n.x - d over that piece's faces that are not kCovered (faces
  // glued to another piece are not a way out), so the returned normal is the
  // least-penetration face on the outside of the body; if x is inside
  // several pieces (on a glued face) the deepest one is returned.
  ClumpDistance signed_distance(const Eigen::Vector3d& x) const;

 private:
  void classify_faces(const std::string& what);
  // Exposed faces with outward normal `up` * z (up = +-1) in the top or bottom plane.
  std::vector<FaceRef> level_faces(double up) const;

  std::vector<ConvexShape> pieces_;
  std::vector<std::vector<FaceCover>> cover_;
  std::vector<std::vector<double>> covered_fraction_;
  std::vector<std::vector<int>> open_faces_;  // per piece: faces that are not kCovered
  std::vector<std::string> notes_;
  double tolerance_ = 0.0;
};

// Mass properties of rigidly joined parts (each about its own COM, in a common
// frame) combined with the parallel-axis theorem.
MassProperties combine_mass_properties(const std::vector<MassProperties>& parts);

}  // namespace freestand

#endif
