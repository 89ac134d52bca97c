#include "freestand/convex_shape.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "freestand/input_error.h"

namespace freestand {

using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Relative geometric tolerance: distances below kRelTol times the
// bounding-box diagonal are treated as zero.
constexpr double kRelTol = 1e-9;

std::string vec_str(const Vector3d& v) { return fmt::format("({:.9g}, {:.9g}, {:.9g})", v.x(), v.y(), v.z()); }

// Twice the vector area of a planar polygon (Newell's method, exact for planar loops).
Vector3d newell(const std::vector<Vector3d>& v, const std::vector<int>& loop) {
  Vector3d sum = Vector3d::Zero();
  const Vector3d& o = v[loop[0]];
  for (size_t k = 1; k + 1 < loop.size(); ++k) sum += (v[loop[k]] - o).cross(v[loop[k + 1]] - o);
  return sum;
}

}  // namespace

// ---------------------------------------------------------------------------
// Mass properties: divergence theorem through signed tetrahedra.
//
// Every face loop is fanned from its first vertex into triangles (a, b, c);
// with the reference point r (the mean of the vertices) each triangle spans
// the tetrahedron (r, a, b, c) of signed volume det[a', b', c'] / 6, primes
// meaning relative to r. Summed over the closed surface the signed tetrahedra
// tile the solid exactly (Mirtich 1996; Tonon 2004), so
//   V   = sum det / 6
//   S   = sum det / 24 (a' + b' + c')                 (first moment)
//   C   = sum det / 120 (a'a'^T + b'b'^T + c'c'^T + s s^T),  s = a' + b' + c'
// are exact: C is the second-moment (covariance) tensor int x' x'^T dV of the
// tetrahedron with a vertex at the origin. Then g = S / V, C_g = C - V g g^T
// and the inertia at unit density is tr(C_g) 1 - C_g.
MassProperties polyhedron_mass_properties(const std::vector<Vector3d>& vertices,
                                          const std::vector<std::vector<int>>& loops) {
  Vector3d r = Vector3d::Zero();
  for (const Vector3d& v : vertices) r += v;
  r /= static_cast<double>(vertices.size());

  double six_v = 0.0;
  Vector3d s24 = Vector3d::Zero();
  Matrix3d c120 = Matrix3d::Zero();
  for (const auto& loop : loops) {
    const Vector3d a = vertices[loop[0]] - r;
    for (size_t k = 1; k + 1 < loop.size(); ++k) {
      const Vector3d b = vertices[loop[k]] - r;
      const Vector3d c = vertices[loop[k + 1]] - r;
      const double det = a.dot(b.cross(c));
      const Vector3d s = a + b + c;
      six_v += det;
      s24 += det * s;
      c120 += det * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
    }
  }
  MassProperties m;
  m.volume = six_v / 6.0;
  m.mass = m.volume;
  const Vector3d g = s24 / 24.0 / m.volume;
  m.com = r + g;
  Matrix3d cg = c120 / 120.0 - m.volume * g * g.transpose();
  cg = 0.5 * (cg + cg.transpose());
  m.inertia = cg.trace() * Matrix3d::Identity() - cg;
  return m;
}

// ---------------------------------------------------------------------------
ConvexShape ConvexShape::box(const Vector3d& half_extents) {
  if (!half_extents.allFinite() || (half_extents.array() <= 0.0).any())
    throw InputError(fmt::format("box: half_extents must be positive and finite, got [{}, {}, {}]",
                                 half_extents.x(), half_extents.y(), half_extents.z()));
  const double a = half_extents.x(), b = half_extents.y(), h = 2.0 * half_extents.z();
  std::vector<Vector3d> v = {{-a, -b, 0}, {a, -b, 0}, {a, b, 0}, {-a, b, 0},
                             {-a, -b, h}, {a, -b, h}, {a, b, h}, {-a, b, h}};
  std::vector<std::vector<int>> loops = {{0, 3, 2, 1}, {4, 5, 6, 7}};
  for (int k = 0; k < 4; ++k) loops.push_back({k, (k + 1) % 4, (k + 1) % 4 + 4, k + 4});
  return from_loops(std::move(v), std::move(loops), "box");
}

ConvexShape ConvexShape::prism(double radius, int sides, double height) {
  if (!(std::isfinite(radius) && radius > 0.0))
    throw InputError(fmt::format("prism: radius must be positive and finite, got {}", radius));
  if (!(std::isfinite(height) && height > 0.0))
    throw InputError(fmt::format("prism: height must be positive and finite, got {}", height));
  if (sides < 3) throw InputError(fmt::format("prism: sides must be at least 3, got {}", sides));
  std::vector<Vector3d> v(2 * sides);
  for (int k = 0; k < sides; ++k) {
    const double t = (2 * k + 1) * kPi / sides;
    v[k] = Vector3d(radius * std::cos(t), radius * std::sin(t), 0.0);
    v[k + sides] = Vector3d(v[k].x(), v[k].y(), height);
  }
  std::vector<std::vector<int>> loops(2);
  for (int k = 0; k < sides; ++k) {
    loops[0].push_back((sides - k) % sides);  // base: clockwise seen from above
    loops[1].push_back(k + sides);
  }
  for (int k = 0; k < sides; ++k) {
    const int k1 = (k + 1) % sides;
    loops.push_back({k, k1, k1 + sides, k + sides});
  }
  return from_loops(std::move(v), std::move(loops), "prism");
}

ConvexShape ConvexShape::transformed(const Matrix3d& rotation, const Vector3d& offset) const {
  if (!rotation.allFinite() || !offset.allFinite() ||
      (rotation.transpose() * rotation - Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 ||
      std::abs(rotation.determinant() - 1.0) > 1e-9)
    throw InputError("shape placement: the orientation must be a proper rotation (orthonormal, det +1) "
                     "and the offset finite");
  std::vector<Vector3d> v(vertices_.size());
  for (size_t i = 0; i < v.size(); ++i) v[i] = rotation * vertices_[i] + offset;
  std::vector<std::vector<int>> loops;
  std::vector<Vector3d> normals;
  for (const ShapeFace& f : faces_) {
    loops.push_back(f.loop);
    normals.push_back(rotation * f.normal);
  }
  ConvexShape s = from_loops(std::move(v), std::move(loops), "shape placement", &normals);
  s.source_index_ = source_index_;
  s.notes_ = notes_;
  return s;
}

ConvexShape ConvexShape::from_loops(std::vector<Vector3d> vertices, std::vector<std::vector<int>> loops,
                                    const std::string& what, const std::vector<Vector3d>* normals) {
  ConvexShape s;
  s.vertices_ = std::move(vertices);
  s.source_index_.resize(s.vertices_.size());
  for (size_t i = 0; i < s.vertices_.size(); ++i) s.source_index_[i] = static_cast<int>(i);
  s.faces_.resize(loops.size());
  for (size_t f = 0; f < loops.size(); ++f) s.faces_[f].loop = std::move(loops[f]);
  s.finish(what, normals);
  return s;
}

void ConvexShape::finish(const std::string& what, const std::vector<Vector3d>* normals) {
  const int nv = static_cast<int>(vertices_.size());
  const int nf = static_cast<int>(faces_.size());
  box_.setEmpty();
  for (const Vector3d& v : vertices_) {
    if (!v.allFinite()) throw InputError(what + ": non-finite vertex coordinate");
    box_.extend(v);
  }
  tolerance_ = kRelTol * box_.diagonal().norm();
  if (nv < 4 || nf < 4) throw InputError(fmt::format("{}: a polyhedron needs at least 4 vertices and 4 faces", what));

  // Planes, areas, centroids.
  for (int f = 0; f < nf; ++f) {
    ShapeFace& face = faces_[f];
    if (face.loop.size() < 3) throw InputError(fmt::format("{}: face {} has fewer than 3 vertices", what, f));
    for (int i : face.loop)
      if (i < 0 || i >= nv) throw InputError(fmt::format("{}: face {} names vertex {} of {}", what, f, i, nv));
    const Vector3d twice_area = newell(vertices_, face.loop);
    face.normal = normals ? normals->at(f).normalized() : twice_area.normalized();
    face.area = 0.5 * twice_area.dot(face.normal);
    if (!(face.area > tolerance_ * tolerance_))
      throw InputError(fmt::format("{}: face {} has zero area", what, f));
    // Offset: mean of n.v over the loop, summed as deviations from the first
    // vertex so that an exactly planar loop gets its exact offset.
    const double d0 = face.normal.dot(vertices_[face.loop[0]]);
    double dev = 0.0;
    for (int i : face.loop) dev += face.normal.dot(vertices_[i]) - d0;
    face.offset = d0 + dev / static_cast<double>(face.loop.size());
    // Area centroid from the fan about the first vertex.
    Vector3d moment = Vector3d::Zero();
    const Vector3d& o = vertices_[face.loop[0]];
    for (size_t k = 1; k + 1 < face.loop.size(); ++k) {
      const Vector3d& b = vertices_[face.loop[k]];
      const Vector3d& c = vertices_[face.loop[k + 1]];
      const double a2 = (b - o).cross(c - o).dot(face.normal);
      moment += a2 * (o + b + c);
    }
    face.centroid = moment / (6.0 * face.area);
  }

  // Convexity, to 10 x the tolerance (a hull merges facets within the
  // tolerance of a seed plane, so its corners may sit a little off the fitted
  // plane): every vertex on the inner side of every face plane, each loop
  // vertex on its plane, no loop turning right.
  const double slack = 10.0 * tolerance_;
  for (int f = 0; f < nf; ++f) {
    const ShapeFace& face = faces_[f];
    for (int i = 0; i < nv; ++i) {
      const double s = face.normal.dot(vertices_[i]) - face.offset;
      if (s > slack)
        throw InputError(fmt::format("{}: not convex: vertex {} {} lies {:.3g} m outside face {}", what, i,
                                     vec_str(vertices_[i]), s, f));
    }
    const size_t m = face.loop.size();
    for (size_t k = 0; k < m; ++k) {
      const Vector3d& p = vertices_[face.loop[k]];
      if (std::abs(face.normal.dot(p) - face.offset) > slack)
        throw InputError(fmt::format("{}: face {} is not planar at vertex {}", what, f, face.loop[k]));
      const Vector3d& q = vertices_[face.loop[(k + 1) % m]];
      const Vector3d& r = vertices_[face.loop[(k + 2) % m]];
      const Vector3d e = q - p;
      const double turn = e.cross(r - q).dot(face.normal) / (r - q).norm();
      if (turn < -slack)
        throw InputError(fmt::format("{}: face {} is not convex at vertex {}", what, f, face.loop[(k + 1) % m]));
    }
  }

  // Edges: every directed loop edge must be matched by the reverse edge of
  // exactly one other face (a closed 2-manifold).
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < nf; ++f) {
    const auto& loop = faces_[f].loop;
    for (size_t k = 0; k < loop.size(); ++k) {
      const std::pair<int, int> e(loop[k], loop[(k + 1) % loop.size()]);
      if (!directed.emplace(e, f).second)
        throw InputError(fmt::format("{}: edge {}-{} is used twice in the same direction", what, e.first, e.second));
    }
  }
  edges_.clear();
  std::map<std::pair<int, int>, int> edge_index;
  for (const auto& [e, f] : directed) {
    auto rev = directed.find({e.second, e.first});
    if (rev == directed.end())
      throw InputError(fmt::format("{}: edge {}-{} of face {} has no neighbouring face (surface not closed)", what,
                                   e.first, e.second, f));
    if (e.first < e.second) {
      edge_index[e] = static_cast<int>(edges_.size());
      edge_index[{e.second, e.first}] = static_cast<int>(edges_.size());
      edges_.push_back({e.first, e.second, f, rev->second});
    }
  }
  std::vector<int> used(nv, 0);
  for (const ShapeFace& face : faces_)
    for (int i : face.loop) used[i] = 1;
  for (int i = 0; i < nv; ++i)
    if (!used[i]) throw InputError(fmt::format("{}: vertex {} is on no face", what, i));
  if (nv - static_cast<int>(edges_.size()) + nf != 2)
    throw InputError(fmt::format("{}: V - E + F = {} - {} + {} != 2: not a convex polyhedron", what, nv,
                                 edges_.size(), nf));

  std::vector<std::vector<int>> loops;
  for (const ShapeFace& face : faces_) loops.push_back(face.loop);
  mass_ = polyhedron_mass_properties(vertices_, loops);
  if (!(mass_.volume > 0.0)) throw InputError(fmt::format("{}: zero or negative volume", what));

  normals_.resize(nf);
  offsets_.resize(nf);
  loop_begin_.assign(1, 0);
  loop_vertex_.clear();
  loop_edge_.clear();
  for (int f = 0; f < nf; ++f) {
    normals_[f] = faces_[f].normal;
    offsets_[f] = faces_[f].offset;
    const auto& loop = faces_[f].loop;
    for (size_t k = 0; k < loop.size(); ++k) {
      loop_vertex_.push_back(loop[k]);
      loop_edge_.push_back(edge_index.at({loop[k], loop[(k + 1) % loop.size()]}));
    }
    loop_begin_.push_back(static_cast<int>(loop_vertex_.size()));
  }
}

MassProperties ConvexShape::mass_properties(double density) const {
  if (!(std::isfinite(density) && density > 0.0))
    throw InputError(fmt::format("density must be positive and finite, got {}", density));
  MassProperties m = mass_;
  m.mass = density * m.volume;
  m.inertia *= density;
  return m;
}

double ConvexShape::bounding_radius(const Vector3d& centre) const {
  double r2 = 0.0;
  for (const Vector3d& v : vertices_) r2 = std::max(r2, (v - centre).squaredNorm());
  return std::sqrt(r2);
}

PlaneDistance ConvexShape::max_plane_distance(const Vector3d& x) const {
  PlaneDistance out{-std::numeric_limits<double>::infinity(), -1};
  const int nf = static_cast<int>(normals_.size());
  for (int f = 0; f < nf; ++f) {
    const double s = normals_[f].dot(x) - offsets_[f];
    if (s > out.value) {
      out.value = s;
      out.face = f;
    }
  }
  // A NaN point (a body that blew up) must not look deeply inside.
  if (out.face < 0) out = {std::numeric_limits<double>::quiet_NaN(), 0};
  return out;
}

SurfaceDistance ConvexShape::signed_distance(const Vector3d& x) const {
  const PlaneDistance pd = max_plane_distance(x);
  SurfaceDistance out;
  if (pd.value <= 0.0) {
    out.distance = pd.value;
    out.face = pd.face;
    out.normal = normals_[pd.face];
    out.point = x - pd.value * out.normal;
    out.feature = SurfaceFeature::kFace;
    out.feature_index = pd.face;
    return out;
  }
  // Outside: the closest point lies on a face whose plane separates x from
  // the solid (n.x - d > 0); take the closest point over those faces.
  double best2 = std::numeric_limits<double>::infinity();
  const int nf = static_cast<int>(normals_.size());
  for (int f = 0; f < nf; ++f) {
    const Vector3d& n = normals_[f];
    const double s = n.dot(x) - offsets_[f];
    if (s <= 0.0 || s * s >= best2) continue;
    const Vector3d q = x - s * n;
    const int b = loop_begin_[f], e = loop_begin_[f + 1];
    bool inside = true;
    for (int k = b; k < e; ++k) {
      const Vector3d& p0 = vertices_[loop_vertex_[k]];
      const Vector3d& p1 = vertices_[loop_vertex_[k + 1 < e ? k + 1 : b]];
      if ((p1 - p0).cross(q - p0).dot(n) < 0.0) {
        inside = false;
        break;
      }
    }
    if (inside) {
      best2 = s * s;
      out.point = q;
      out.face = f;
      out.feature = SurfaceFeature::kFace;
      out.feature_index = f;
      continue;
    }
    for (int k = b; k < e; ++k) {
      const int i0 = loop_vertex_[k], i1 = loop_vertex_[k + 1 < e ? k + 1 : b];
      const Vector3d& p0 = vertices_[i0];
      const Vector3d edge = vertices_[i1] - p0;
      const double t = std::clamp((x - p0).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
      const Vector3d p = p0 + t * edge;
      const double d2 = (x - p).squaredNorm();
      if (d2 < best2) {
        best2 = d2;
        out.point = p;
        out.face = f;
        if (t <= 0.0) {
          out.feature = SurfaceFeature::kVertex;
          out.feature_index = i0;
        } else if (t >= 1.0) {
          out.feature = SurfaceFeature::kVertex;
          out.feature_index = i1;
        } else {
          out.feature = SurfaceFeature::kEdge;
          out.feature_index = loop_edge_[k];
        }
      }
    }
  }
  out.distance = std::sqrt(best2);
  out.normal = (x - out.point) / out.distance;
  return out;
}

}  // namespace freestand
