// Body-on-body node contact. docs/contact-law.md, "Body-on-body contact".

#include "freestand/body_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "freestand/input_error.h"

namespace freestand {

using Eigen::Matrix3d;
using Eigen::Vector3d;

BodyContactModel::BodyContactModel(const Clump& geometry, const Vector3d& com,
                                   const std::vector<ContactNode>& nodes)
    : com_(com), nodes_(nodes), tolerance_(geometry.tolerance()) {
  const auto& pieces = geometry.pieces();
  pieces_.resize(pieces.size());
  box_.setEmpty();
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const ConvexShape& shape = pieces[k];
    Piece& p = pieces_[k];
    for (std::size_t f = 0; f < shape.faces().size(); ++f) {
      p.normal.push_back(shape.faces()[f].normal);
      p.offset.push_back(shape.faces()[f].offset);
      p.open.push_back(geometry.cover({static_cast<int>(k), static_cast<int>(f)}) !=
                       FaceCover::kCovered);
    }
    p.box = shape.bounding_box();
    box_.extend(p.box);
    for (const Vector3d& v : shape.vertices()) radius_ = std::max(radius_, (v - com).norm());
  }
  node_face_area_.reserve(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const ContactNode& n = nodes_[i];
    if (n.piece < 0 || n.piece >= static_cast<int>(pieces.size()) || n.face < 0 ||
        n.face >= static_cast<int>(pieces[n.piece].faces().size()))
      throw InputError("body contact: node " + std::to_string(i) + " names piece " +
                       std::to_string(n.piece) + ", face " + std::to_string(n.face) +
                       ", which the body does not have");
    node_face_area_.push_back(pieces[n.piece].faces()[n.face].area);
    radius_ = std::max(radius_, (n.position - com).norm());
    box_.extend(n.position);
  }
}

double resolved_band(const BodyContactModel& a, const BodyContactModel& b,
                     const BodyContactOptions& options) {
  if (options.band > 0.0) return options.band;
  return 1e-3 * std::min(a.diagonal(), b.diagonal());
}

namespace {

// Nodes of N (motion mn) against the faces of F (motion mf).
void one_pass(const BodyContactModel& N, const BodyMotion& mn, const BodyContactModel& F,
              const BodyMotion& mf, ContactSide side, double band, const BodyContactOptions& options,
              const BodyMotion& ma, const BodyMotion& mb, std::vector<NodeContact>& out) {
  if (N.nodes().empty()) return;
  const double tau = F.tolerance();  // lateral skin: flush faces stay in contact
  // Broad phase 1: bounding spheres about the COMs.
  const Vector3d d = mn.position - mf.position;
  const double reach = N.bounding_radius() + F.bounding_radius() + tau;
  if (!(d.squaredNorm() <= reach * reach)) return;  // also rejects NaN poses
  const Matrix3d Rn = mn.orientation.toRotationMatrix();
  const Matrix3d Rf = mf.orientation.toRotationMatrix();
  const Matrix3d RfT = Rf.transpose();
  // Broad phase 2: N's sphere against F's box, in F's frame.
  Eigen::AlignedBox3d fbox = F.box();
  fbox.min().array() -= tau;
  fbox.max().array() += tau;
  const Vector3d centre_in_f = RfT * d + F.com();
  if (fbox.exteriorDistance(centre_in_f) > N.bounding_radius()) return;
  // Node body frame -> face body frame, once per pair: p_F = R y + t.
  const Matrix3d R = RfT * Rn;
  const Vector3d t = RfT * (d - Rn * N.com()) + F.com();

  const auto& pieces = F.pieces();
  const int np = static_cast<int>(pieces.size());
  const auto& nodes = N.nodes();
  const int nn = static_cast<int>(nodes.size());
  for (int i = 0; i < nn; ++i) {
    const ContactNode& node = nodes[i];
    const Vector3d p = R * node.position + t;
    if (!fbox.contains(p)) continue;
    // Piece: the deepest one holding p (within tau), as Clump::signed_distance.
    int best_piece = -1;
    double best_open = std::numeric_limits<double>::infinity();
    for (int k = 0; k < np; ++k) {
      const BodyContactModel::Piece& pc = pieces[k];
      if (pc.box.exteriorDistance(p) > tau) continue;
      double s_max = -std::numeric_limits<double>::infinity();
      double s_open = -std::numeric_limits<double>::infinity();
      const int nf = static_cast<int>(pc.normal.size());
      for (int f = 0; f < nf; ++f) {
        const double s = pc.normal[f].dot(p) - pc.offset[f];
        s_max = std::max(s_max, s);
        if (pc.open[f]) s_open = std::max(s_open, s);
      }
      if (!(s_max <= tau)) continue;  // outside this piece (or NaN)
      if (s_open < best_open) {
        best_open = s_open;
        best_piece = k;
      }
    }
    if (best_piece < 0) continue;
    // Face: among the open faces penetrated (s < 0) within `band` of the
    // least depth, the one most anti-parallel to the node's normal; ties
    // (1e-12) to the shallower face, then the lower index.
    const BodyContactModel::Piece& pc = pieces[best_piece];
    const Vector3d m = R * node.normal;
    const double floor_s = best_open - band;
    int best_face = -1;
    double best_dot = std::numeric_limits<double>::infinity();
    double best_s = 0.0;
    const int nf = static_cast<int>(pc.normal.size());
    for (int f = 0; f < nf; ++f) {
      if (!pc.open[f]) continue;
      const double s = pc.normal[f].dot(p) - pc.offset[f];
      if (!(s < 0.0) || s < floor_s) continue;
      const double dot = m.dot(pc.normal[f]);
      if (dot < best_dot - 1e-12 || (dot <= best_dot + 1e-12 && s > best_s)) {
        best_face = f;
        best_dot = dot;
        best_s = s;
      }
    }
    if (best_face < 0) continue;
    const double facing = -best_dot;
    if (!(facing > options.min_facing)) continue;

    NodeContact c;
    c.side = side;
    c.node = i;
    c.piece = best_piece;
    c.face = best_face;
    c.key = 2u * static_cast<std::uint64_t>(i) + static_cast<std::uint64_t>(side);
    c.normal = Rf * pc.normal[best_face];
    c.overlap = -best_s;
    c.point = mn.position + Rn * (node.position - N.com());
    c.lever_a = c.point - ma.position;
    c.lever_b = c.point - mb.position;
    const Vector3d rn = c.point - mn.position, rf = c.point - mf.position;
    c.velocity = (mn.velocity + mn.angular_velocity.cross(rn)) -
                 (mf.velocity + mf.angular_velocity.cross(rf));
    c.facing = facing;
    c.area = options.pass_weight * facing * node.area;
    c.node_face_area = N.node_face_area(i);
    out.push_back(c);
  }
}

}  // namespace

void find_node_contacts(const BodyContactModel& a, const BodyMotion& motion_a,
                        const BodyContactModel& b, const BodyMotion& motion_b, ContactSide side,
                        double band, const BodyContactOptions& options,
                        std::vector<NodeContact>& out) {
  if (side == ContactSide::kNodeOfA)
    one_pass(a, motion_a, b, motion_b, side, band, options, motion_a, motion_b, out);
  else
    one_pass(b, motion_b, a, motion_a, side, band, options, motion_a, motion_b, out);
}

std::size_t find_body_contacts(const BodyContactModel& a, const BodyMotion& motion_a,
                               const BodyContactModel& b, const BodyMotion& motion_b,
                               const BodyContactOptions& options, std::vector<NodeContact>& out) {
  out.clear();
  const double band = resolved_band(a, b, options);
  one_pass(a, motion_a, b, motion_b, ContactSide::kNodeOfA, band, options, motion_a, motion_b, out);
  one_pass(b, motion_b, a, motion_a, ContactSide::kNodeOfB, band, options, motion_a, motion_b, out);
  return out.size();
}

ContactPoint to_contact_point(const NodeContact& c, double reduced_mass) {
  ContactPoint p;
  p.normal = c.normal;
  p.overlap = c.overlap;
  p.velocity = c.velocity;
  p.area = c.area;
  p.effective_mass = reduced_mass * c.area / c.node_face_area;
  return p;
}

void apply_node_force(const NodeContact& c, const Vector3d& force, Vector3d& force_a,
                      Vector3d& torque_a, Vector3d& force_b, Vector3d& torque_b) {
  const Vector3d fa = c.side == ContactSide::kNodeOfA ? force : Vector3d(-force);
  force_a += fa;
  torque_a += c.lever_a.cross(fa);
  force_b -= fa;
  torque_b -= c.lever_b.cross(fa);
}

}  // namespace freestand
