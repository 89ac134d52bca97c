#include "freestand/contact_nodes.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "freestand/input_error.h"

namespace freestand {

using Eigen::Vector3d;

namespace {

// Segments for a length at spacing h (count mode: `count`). The 1e-9 keeps a
// length that is an exact multiple of h from getting an extra segment.
int segments(double length, const NodeOptions& o, int count) {
  if (o.spacing > 0.0) return std::max(1, static_cast<int>(std::ceil(length / o.spacing - 1e-9)));
  return count;
}

struct Builder {
  PolygonNodes out;
  std::vector<int> boundary;  // node ids counter-clockwise along the polygon boundary

  int add(const Vector3d& p, int corner, NodeKind kind) {
    out.position.push_back(p);
    out.area.push_back(0.0);
    out.corner.push_back(corner);
    out.kind.push_back(kind);
    return static_cast<int>(out.position.size()) - 1;
  }
  // A triangle of the tiling hands a third of its area to each corner: exact
  // area and first moment for each triangle, hence for the face.
  void triangle(int a, int b, int c, const Vector3d& n) {
    const Vector3d& pa = out.position[a];
    const double area = 0.5 * std::abs((out.position[b] - pa).cross(out.position[c] - pa).dot(n));
    out.area[a] += area / 3.0;
    out.area[b] += area / 3.0;
    out.area[c] += area / 3.0;
  }
};

// Parallelogram p0 p1 p2 p3: nu x nv parallelogram cells, each handing a
// quarter of its area to each corner (the mean of a parallelogram's corners
// is its centroid, so this is exact).
void parallelogram(const std::vector<Vector3d>& p, double area, const NodeOptions& o, Builder* b) {
  const int nu = segments((p[1] - p[0]).norm(), o, o.per_edge);
  const int nv = segments((p[3] - p[0]).norm(), o, o.per_edge);
  std::vector<int> id((nu + 1) * (nv + 1));
  const double quarter = area / (4.0 * nu * nv);
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      const double s = static_cast<double>(i) / nu, t = static_cast<double>(j) / nv;
      const Vector3d x = (1 - s) * (1 - t) * p[0] + s * (1 - t) * p[1] + s * t * p[2] + (1 - s) * t * p[3];
      const bool iu = i == 0 || i == nu, jv = j == 0 || j == nv;
      int corner = -1;
      if (iu && jv) corner = (i == 0) ? (j == 0 ? 0 : 3) : (j == 0 ? 1 : 2);
      const NodeKind kind = corner >= 0 ? NodeKind::kVertex : (iu || jv) ? NodeKind::kEdge : NodeKind::kInterior;
      const int k = b->add(corner >= 0 ? p[corner] : x, corner, kind);
      b->out.area[k] = quarter * (iu ? 1 : 2) * (jv ? 1 : 2);
      id[j * (nu + 1) + i] = k;
    }
  for (int i = 0; i < nu; ++i) b->boundary.push_back(id[i]);
  for (int j = 0; j < nv; ++j) b->boundary.push_back(id[j * (nu + 1) + nu]);
  for (int i = nu; i > 0; --i) b->boundary.push_back(id[nv * (nu + 1) + i]);
  for (int j = nv; j > 0; --j) b->boundary.push_back(id[j * (nu + 1)]);
}

// Triangle p0 p1 p2: the barycentric lattice with n segments per edge, n^2
// sub-triangles of equal area, a third of each to its corners.
void triangle(const std::vector<Vector3d>& p, double area, const NodeOptions& o, Builder* b) {
  const double longest = std::max({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()});
  const int n = segments(longest, o, o.per_edge);
  auto index = [n](int i, int j) { return j * (n + 1) - j * (j - 1) / 2 + i; };  // i + j <= n
  std::vector<int> id((n + 1) * (n + 2) / 2);
  const double third = area / (3.0 * n * n);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i + j <= n; ++i) {
      const int l = n - i - j;
      int corner = -1;
      if (i == n) corner = 1;
      if (j == n) corner = 2;
      if (l == n) corner = 0;
      const int zeros = (i == 0) + (j == 0) + (l == 0);
      const NodeKind kind = corner >= 0 ? NodeKind::kVertex : zeros ? NodeKind::kEdge : NodeKind::kInterior;
      const Vector3d x = corner >= 0 ? p[corner] : ((l * p[0] + i * p[1] + j * p[2]) / n).eval();
      const int k = b->add(x, corner, kind);
      b->out.area[k] = third * (corner >= 0 ? 1 : zeros ? 3 : 6);
      id[index(i, j)] = k;
    }
  for (int i = 0; i < n; ++i) b->boundary.push_back(id[index(i, 0)]);
  for (int j = 0; j < n; ++j) b->boundary.push_back(id[index(n - j, j)]);
  for (int j = n; j > 0; --j) b->boundary.push_back(id[index(0, j)]);
}

// Any convex polygon: rings. Ring r (r = 1..R) is the polygon scaled by r/R
// about its centroid c; edge k of ring r is cut into q(r, k) segments. The
// band between consecutive rings is tiled by triangles zipped between the two
// parallel point rows of each edge; ring 1 is fanned from c.
void rings(const std::vector<Vector3d>& p, const Vector3d& c, const Vector3d& nrm, const NodeOptions& o,
           Builder* b) {
  const int m = static_cast<int>(p.size());
  double spoke = 0.0;
  for (const Vector3d& v : p) spoke = std::max(spoke, (v - c).norm());
  const int nr = segments(spoke, o, o.per_edge);
  const int centre = b->add(c, -1, NodeKind::kInterior);
  // ring[r][k]: node ids along edge k of ring r, from corner k to corner k+1 (inclusive).
  std::vector<std::vector<std::vector<int>>> ring(nr + 1);
  for (int r = 1; r <= nr; ++r) {
    const double s = static_cast<double>(r) / nr;
    const bool outer = r == nr;
    std::vector<int> corner_id(m);
    for (int k = 0; k < m; ++k)
      corner_id[k] = b->add(outer ? p[k] : (c + s * (p[k] - c)).eval(), outer ? k : -1,
                            outer ? NodeKind::kVertex : NodeKind::kInterior);
    ring[r].resize(m);
    for (int k = 0; k < m; ++k) {
      const int k1 = (k + 1) % m;
      const int q = segments(s * (p[k1] - p[k]).norm(), o, r);
      const Vector3d a = b->out.position[corner_id[k]], e = b->out.position[corner_id[k1]] - a;
      ring[r][k].push_back(corner_id[k]);
      for (int j = 1; j < q; ++j)
        ring[r][k].push_back(b->add(a + (static_cast<double>(j) / q) * e, -1,
                                    outer ? NodeKind::kEdge : NodeKind::kInterior));
      ring[r][k].push_back(corner_id[k1]);
    }
  }
  for (int k = 0; k < m; ++k) {
    const std::vector<int>& first = ring[1][k];
    for (size_t j = 0; j + 1 < first.size(); ++j) b->triangle(centre, first[j], first[j + 1], nrm);
    for (int r = 2; r <= nr; ++r) {
      const std::vector<int>& in = ring[r - 1][k];
      const std::vector<int>& out = ring[r][k];
      const int qi = static_cast<int>(in.size()) - 1, qo = static_cast<int>(out.size()) - 1;
      int i = 0, j = 0;
      while (i < qi || j < qo) {
        // Advance along the row whose next point comes first (as a fraction of the edge).
        if (j < qo && (i == qi || static_cast<double>(j + 1) / qo <= static_cast<double>(i + 1) / qi)) {
          b->triangle(in[i], out[j], out[j + 1], nrm);
          ++j;
        } else {
          b->triangle(in[i], out[j], in[i + 1], nrm);
          ++i;
        }
      }
    }
  }
  for (int k = 0; k < m; ++k)
    for (size_t j = 0; j + 1 < ring[nr][k].size(); ++j) b->boundary.push_back(ring[nr][k][j]);
}

bool has_face(const Clump& body, const FaceRef& ref) {
  return ref.piece >= 0 && ref.piece < static_cast<int>(body.pieces().size()) && ref.face >= 0 &&
         ref.face < static_cast<int>(body.pieces()[ref.piece].faces().size());
}

}  // namespace

PolygonNodes polygon_nodes(const std::vector<Vector3d>& loop, const Vector3d& normal, const NodeOptions& options) {
  NodeOptions o = options;
  // Area and centroid (fan about the first corner).
  const size_t m = loop.size();
  double area = 0.0;
  Vector3d moment = Vector3d::Zero();
  for (size_t k = 1; k + 1 < m; ++k) {
    const double a = 0.5 * (loop[k] - loop[0]).cross(loop[k + 1] - loop[0]).dot(normal);
    area += a;
    moment += a * (loop[0] + loop[k] + loop[k + 1]) / 3.0;
  }
  const Vector3d centroid = moment / area;
  double scale = 0.0, diameter = 0.0;
  for (const Vector3d& v : loop) {
    scale = std::max(scale, (v - centroid).norm());
    for (const Vector3d& w : loop) diameter = std::max(diameter, (v - w).norm());
  }
  const bool parallelogram_face = m == 4 && (loop[0] + loop[2] - loop[1] - loop[3]).norm() <= 1e-12 * scale;
  // A triangle or polygon narrower than the spacing (area / diameter < h/2, a
  // sliver) gets vertex nodes only: its lattice would put ~(diameter/h)^2
  // nodes on almost no area, and its long edges are noded by its neighbours.
  if (o.layout == NodeLayout::kVertices ||
      (o.spacing > 0.0 && !parallelogram_face && area / diameter < 0.5 * o.spacing)) {
    o.layout = NodeLayout::kVertices;
    o.spacing = 0.0;
    o.per_edge = 1;
  }

  Builder b;
  if (m == 3) {
    triangle(loop, area, o, &b);
  } else if (parallelogram_face) {
    parallelogram(loop, area, o, &b);
  } else {
    rings(loop, centroid, normal, o, &b);
  }
  if (o.layout == NodeLayout::kSurface) return b.out;

  // Boundary layouts: move every interior node's area onto the boundary nodes.
  std::vector<Vector3d> poly;
  for (int id : b.boundary) poly.push_back(b.out.position[id]);
  std::vector<double> w;
  for (size_t i = 0; i < b.out.position.size(); ++i) {
    if (b.out.kind[i] != NodeKind::kInterior) continue;
    polygon_weights(poly, b.out.position[i], normal, 0.0, &w);  // interior: mean value coordinates
    for (size_t k = 0; k < poly.size(); ++k) b.out.area[b.boundary[k]] += w[k] * b.out.area[i];
  }
  PolygonNodes kept;
  for (int id : b.boundary) {
    kept.position.push_back(b.out.position[id]);
    kept.area.push_back(b.out.area[id]);
    kept.corner.push_back(b.out.corner[id]);
    kept.kind.push_back(b.out.kind[id]);
  }
  return kept;
}

std::vector<ContactNode> make_contact_nodes(const Clump& body, const NodeOptions& options) {
  if (!(std::isfinite(options.spacing) && options.spacing >= 0.0))
    throw InputError(fmt::format("contact nodes: spacing must be >= 0 and finite, got {}", options.spacing));
  if (options.spacing == 0.0 && options.per_edge < 1)
    throw InputError(fmt::format("contact nodes: per_edge must be at least 1, got {}", options.per_edge));
  std::vector<FaceRef> faces = options.faces;
  if (faces.empty()) {
    for (size_t i = 0; i < body.pieces().size(); ++i)
      for (size_t f = 0; f < body.pieces()[i].faces().size(); ++f) {
        const FaceRef ref{static_cast<int>(i), static_cast<int>(f)};
        if (body.cover(ref) != FaceCover::kCovered) faces.push_back(ref);
      }
  }
  for (size_t a = 0; a < faces.size(); ++a) {
    const FaceRef& ref = faces[a];
    if (!has_face(body, ref))
      throw InputError(fmt::format("contact nodes: no face {} on piece {}", ref.face, ref.piece));
    if (body.cover(ref) == FaceCover::kCovered)
      throw InputError(fmt::format("contact nodes: face {} of piece {} lies against another piece (inside the body)",
                                   ref.face, ref.piece));
    for (size_t b = 0; b < a; ++b)
      if (faces[b] == ref)
        throw InputError(fmt::format("contact nodes: face {} of piece {} is selected twice", ref.face, ref.piece));
  }

  for (const FaceRef& ref : options.refined)  // a refined face without nodes (not in `faces`) is no error
    if (!has_face(body, ref)) throw InputError(fmt::format("contact nodes: no face {} on piece {}", ref.face, ref.piece));
  NodeOptions corners = options;
  corners.spacing = 0.0;
  corners.per_edge = 1;

  std::vector<ContactNode> nodes;
  for (const FaceRef& ref : faces) {
    const ConvexShape& shape = body.pieces()[ref.piece];
    const ShapeFace& face = shape.faces()[ref.face];
    std::vector<Vector3d> loop;
    for (int v : face.loop) loop.push_back(shape.vertices()[v]);
    const bool refined = options.refined.empty() ||
                         std::find(options.refined.begin(), options.refined.end(), ref) != options.refined.end();
    const PolygonNodes pn = polygon_nodes(loop, face.normal, refined ? options : corners);
    for (size_t i = 0; i < pn.position.size(); ++i) {
      ContactNode node;
      node.position = pn.position[i];
      node.normal = face.normal;
      node.area = pn.area[i];
      node.piece = ref.piece;
      node.face = ref.face;
      node.vertex = pn.corner[i] >= 0 ? face.loop[pn.corner[i]] : -1;
      node.kind = pn.kind[i];
      nodes.push_back(node);
    }
  }
  if (!options.base.flat()) {
    // Every face's nodes on the base (the sides' nodes on the base edges too)
    // move together, so they stay one point.
    const BaseMap base(body, options.base);
    for (ContactNode& node : nodes) node.position = base(node.position);
  }
  return nodes;
}

std::vector<ContactNode> make_contact_nodes(const ConvexShape& shape, const NodeOptions& options) {
  return make_contact_nodes(Clump(shape), options);
}

}  // namespace freestand
