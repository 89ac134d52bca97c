#ifndef FREESTAND_PLANE_CONTACT_NODES_H
#define FREESTAND_PLANE_CONTACT_NODES_H

// Contact nodes of a body against a plane (the shake table), on every face,
// so that a body lying on any face (a toppled statue, a drum on its side) is
// held by that face, not only by the rim of its base.
//
// A vertex or edge point belongs to several faces and carries a different
// tributary area on each. Against the plane, the area that acts is the one of
// the face the body currently rests on: of the faces holding a point, the one
// whose outward normal points most nearly down (the lowest n . up). So a
// block standing or rocking on its base presses its base corners with the
// base face's shares only, exactly as a base-only node set does, and the same
// corners carry the side face's shares once the block lies on its side.
// Coplanar faces of a clump (two pieces' base faces meeting at an edge) all
// act at their shared points, as they would as separate nodes.

#include <Eigen/Core>
#include <vector>

#include "freestand/contact_nodes.h"
#include "freestand/shape_clump.h"

namespace freestand {

struct PlaneContactNodes {
  // Per distinct surface point, base-face points first:
  std::vector<Eigen::Vector3d> point;  // from the centre of mass, body frame (m)
  std::vector<int> first_share;        // shares of point k: [first_share[k], first_share[k + 1])
  // Per share (one node of one face at that point):
  std::vector<Eigen::Vector3d> normal;  // outward unit normal of the face, body frame
  std::vector<double> area;             // tributary area of the node on that face (m^2)
  std::vector<double> dashpot_mass;     // m A / A_face: the body's share behind the node (kg)

  std::size_t points() const { return point.size(); }
  std::size_t shares() const { return area.size(); }
  // The shares of point k that act against a plane whose upward unit normal,
  // written in the body frame, is `up`: written to `acting` (room for the
  // point's share count); returns how many.
  int acting_shares(std::size_t k, const Eigen::Vector3d& up, int* acting) const;
};

// The nodes (at `options`' resolution and layout) of every exposed face,
// grouped by position, the base faces' points first in their own order.
// `com`, `mass`: the body's centre of mass (body frame) and mass.
PlaneContactNodes make_plane_contact_nodes(const Clump& body, const Eigen::Vector3d& com, double mass,
                                           const NodeOptions& options);

}  // namespace freestand

#endif
