#ifndef FREESTAND_BODY_CONTACT_H
#define FREESTAND_BODY_CONTACT_H

// Body-on-body node contact: the geometric kernel of `pair_style convex`
// (statue on pedestal, column drums, wall blocks), free of LIGGGHTS types.
//
// Each body carries contact nodes (contact_nodes.h: its vertices plus a grid
// of points on its faces, each with the outward normal of its face and a
// tributary area). For a pair (A, B) the nodes of A are tested against the
// faces of B AND the nodes of B against the faces of A. A node inside the
// other body gives one NodeContact: the normal (a face of the other body), the
// overlap, the contact point (the node), the lever arms from both centres of
// mass, the relative velocity and a stable key for the contact history. The
// caller turns each into a force with ContactLaw::compute (contact_law.h) and
// applies it with apply_node_force(), equal and opposite at the same point.
//
// docs/contact-law.md, section "Body-on-body contact", states the algorithm,
// the choice of the normal near edges and vertices, the weights, and the
// limits. SI units; world frame unless stated.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "freestand/contact_law.h"
#include "freestand/contact_nodes.h"
#include "freestand/shape_clump.h"

namespace freestand {

// What the contact code needs of one body type, prepared once (not per step):
// the nodes, flat copies of every piece's face planes with their cover, piece
// and body bounding boxes, the bounding radius about the COM.
class BodyContactModel {
 public:
  // `geometry` in the body frame (origin at the base-face centre), `com` the
  // centre of mass in the body frame, `nodes` from make_contact_nodes(geometry,
  // ...) (may be empty: such a body only offers faces). Throws InputError if a
  // node names a piece or face the geometry does not have.
  BodyContactModel(const Clump& geometry, const Eigen::Vector3d& com,
                   const std::vector<ContactNode>& nodes);

  struct Piece {
    std::vector<Eigen::Vector3d> normal;  // outward unit face normals (body frame)
    std::vector<double> offset;           // n.x <= offset inside
    std::vector<char> open;               // face not kCovered (a way out of the body)
    Eigen::AlignedBox3d box;              // body frame
  };

  const Eigen::Vector3d& com() const { return com_; }
  const std::vector<Piece>& pieces() const { return pieces_; }
  const std::vector<ContactNode>& nodes() const { return nodes_; }
  // Area of the face holding node i (m^2): for the dashpot's effective mass.
  double node_face_area(int i) const { return node_face_area_[i]; }
  const Eigen::AlignedBox3d& box() const { return box_; }  // body frame
  double bounding_radius() const { return radius_; }       // about the COM, covers the nodes
  double diagonal() const { return box_.diagonal().norm(); }
  double tolerance() const { return tolerance_; }           // Clump::tolerance()

 private:
  Eigen::Vector3d com_;
  std::vector<Piece> pieces_;
  std::vector<ContactNode> nodes_;
  std::vector<double> node_face_area_;
  Eigen::AlignedBox3d box_;
  double radius_ = 0.0;
  double tolerance_ = 0.0;
};

// Pose and velocity of one body.
struct BodyMotion {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();                 // COM, world (m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();    // body -> world, unit
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();                 // of the COM (m/s)
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();         // world (rad/s)
};

struct BodyContactOptions {
  // Normal band (m): among the other body's faces whose depth is within
  // `band` of the least depth, the node takes the face most anti-parallel to
  // its own normal. Must exceed the largest overlap expected (several times
  // ContactLaw::impact_overlap) and stay far below the node spacing. <= 0:
  // 1e-3 times the smaller of the two bodies' bounding-box diagonals.
  double band = 0.0;
  // Weight of each of the two passes (A's nodes on B, B's nodes on A). 0.5:
  // two faces resting on each other (both passes see the whole patch) get
  // exactly k_a per unit area, as against the table; a corner or edge seen by
  // one pass only gets half. 1.0: the reverse.
  double pass_weight = 0.5;
  // A node counts only if its facing factor -m.n (m its normal, n the chosen
  // face's normal) exceeds this; nodes on faces perpendicular to the contact
  // (the side faces of a resting block) have 0 and drop out cleanly.
  double min_facing = 1e-6;
};

// Which body the node belongs to, in the order the pair was given.
enum class ContactSide : std::uint8_t {
  kNodeOfA = 0,  // a node of A inside B, pushed along a face normal of B
  kNodeOfB = 1,  // a node of B inside A, pushed along a face normal of A
};

// One node inside the other body.
struct NodeContact {
  ContactSide side = ContactSide::kNodeOfA;
  int node = -1;        // index in the node body's nodes()
  int piece = -1;       // the other body's piece and face giving the normal
  int face = -1;
  // Stable history identifier within the ordered pair (A, B): 2 * node + side.
  // The caller keys its history by (tag of A, tag of B, key) and passes each
  // pair in a fixed order (e.g. lower tag first), so histories persist.
  std::uint64_t key = 0;
  Eigen::Vector3d normal;    // unit, world: from the face body toward the node body
  double overlap = 0.0;      // depth of the node below that face (m), > 0
  Eigen::Vector3d point;     // contact point = the node, world (m)
  Eigen::Vector3d lever_a;   // point - COM of A (m)
  Eigen::Vector3d lever_b;   // point - COM of B (m)
  Eigen::Vector3d velocity;  // node body's material velocity minus the face body's, at point (m/s)
  double facing = 0.0;       // -m.n in (0, 1]
  double area = 0.0;         // pass_weight * facing * node area: the A of ContactPoint (m^2)
  double node_face_area = 0.0;  // area of the node's face (m^2)
};

// Both passes. Clears `out` and fills it (its capacity is reused: no
// allocation once it has grown). Order: A's nodes in index order, then B's.
// Returns out.size(). The two models may be the same object (two bodies of
// one type).
std::size_t find_body_contacts(const BodyContactModel& a, const BodyMotion& motion_a,
                               const BodyContactModel& b, const BodyMotion& motion_b,
                               const BodyContactOptions& options, std::vector<NodeContact>& out);

// One pass: appends the contacts of `side` only (nodes of A on B's faces for
// kNodeOfA, nodes of B on A's faces for kNodeOfB); `band` as resolved (> 0).
void find_node_contacts(const BodyContactModel& a, const BodyMotion& motion_a,
                        const BodyContactModel& b, const BodyMotion& motion_b, ContactSide side,
                        double band, const BodyContactOptions& options,
                        std::vector<NodeContact>& out);

// The band find_body_contacts uses.
double resolved_band(const BodyContactModel& a, const BodyContactModel& b,
                     const BodyContactOptions& options);

// The ContactLaw input of a contact. Effective mass for the dashpots, as
// recommended in contact_law.h: m_red * area / node_face_area, m_red =
// m_a m_b / (m_a + m_b).
ContactPoint to_contact_point(const NodeContact& c, double reduced_mass);

// Accumulates `force` (N, world, on the NODE's body, as ContactLaw returns
// it) on that body and -force on the other, both at c.point: forces and
// torques about each COM are added to (force_a, torque_a) and (force_b,
// torque_b).
void apply_node_force(const NodeContact& c, const Eigen::Vector3d& force,
                      Eigen::Vector3d& force_a, Eigen::Vector3d& torque_a,
                      Eigen::Vector3d& force_b, Eigen::Vector3d& torque_b);

}  // namespace freestand

#endif
