#include "freestand/plane_contact_nodes.h"

#include <algorithm>
#include <numeric>

namespace freestand {

using Eigen::Vector3d;

namespace {

// Group id of every node: nodes closer than `tolerance` share a point (a
// vertex or edge point computed from two faces' loops may differ by round-off).
std::vector<int> group_by_position(const std::vector<ContactNode>& nodes, double tolerance) {
  std::vector<int> order(nodes.size()), group(nodes.size(), -1);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return nodes[a].position.x() < nodes[b].position.x(); });
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (group[order[i]] >= 0) continue;
    group[order[i]] = order[i];
    for (std::size_t j = i + 1; j < order.size(); ++j) {
      const ContactNode &a = nodes[order[i]], &b = nodes[order[j]];
      if (b.position.x() - a.position.x() > tolerance) break;
      if (group[order[j]] < 0 && (b.position - a.position).norm() <= tolerance) group[order[j]] = order[i];
    }
  }
  return group;
}

bool same_node(const ContactNode& a, const ContactNode& b) {
  return a.piece == b.piece && a.face == b.face && a.position == b.position;
}

}  // namespace

PlaneContactNodes make_plane_contact_nodes(const Clump& body, const Vector3d& com, double mass,
                                           const NodeOptions& options) {
  NodeOptions base = options, all = options;
  base.faces = body.base_faces();
  all.faces.clear();
  std::vector<ContactNode> nodes = make_contact_nodes(body, base);
  const std::size_t base_count = nodes.size();
  for (const ContactNode& node : make_contact_nodes(body, all)) {
    const auto end = nodes.begin() + static_cast<std::ptrdiff_t>(base_count);
    if (std::none_of(nodes.begin(), end, [&](const ContactNode& b) { return same_node(node, b); }))
      nodes.push_back(node);
  }
  const double size = body.bounding_box().diagonal().norm();
  const std::vector<int> group = group_by_position(nodes, 1e-9 * std::max(size, 1.0));

  // Points in order of first appearance; each point's shares in node order.
  std::vector<int> point_of(nodes.size(), -1);  // by group id
  std::vector<std::vector<int>> point_nodes;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    int& p = point_of[group[n]];
    if (p < 0) {
      p = static_cast<int>(point_nodes.size());
      point_nodes.emplace_back();
    }
    point_nodes[p].push_back(static_cast<int>(n));
  }
  PlaneContactNodes out;
  for (const std::vector<int>& members : point_nodes) {
    out.point.push_back(nodes[members.front()].position - com);
    out.first_share.push_back(static_cast<int>(out.area.size()));
    for (int n : members) {
      const ContactNode& node = nodes[n];
      const double face_area = body.pieces()[node.piece].faces()[node.face].area;
      out.normal.push_back(node.normal);
      out.area.push_back(node.area);
      out.dashpot_mass.push_back(mass * node.area / face_area);
    }
  }
  out.first_share.push_back(static_cast<int>(out.area.size()));
  return out;
}

int PlaneContactNodes::acting_shares(std::size_t k, const Vector3d& up, int* acting) const {
  const int begin = first_share[k], end = first_share[k + 1];
  if (end - begin == 1) {
    acting[0] = begin;
    return 1;
  }
  double lowest = 2.0;
  for (int s = begin; s < end; ++s) lowest = std::min(lowest, normal[s].dot(up));
  // Coplanar faces (equal normals up to round-off) act together.
  int count = 0;
  for (int s = begin; s < end; ++s)
    if (normal[s].dot(up) <= lowest + 1e-9) acting[count++] = s;
  return count;
}

}  // namespace freestand
