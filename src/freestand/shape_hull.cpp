// ConvexShape::hull: Qhull (reentrant C library) finds the hull facets; the
// faces are then rebuilt here so that coplanar facets are one face and every
// face loop holds exactly the corners of that face.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "freestand/convex_shape.h"
#include "freestand/input_error.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace freestand {

using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

constexpr double kRelTol = 1e-9;  // same as convex_shape.cpp

std::string pt(const std::vector<Vector3d>& p, int i) {
  return fmt::format("vertices[{}] ({:.9g}, {:.9g}, {:.9g})", i, p[i].x(), p[i].y(), p[i].z());
}

// One hull facet as Qhull reports it: n.x <= d inside, its vertices (input
// indices) counter-clockwise seen from outside.
struct Facet {
  Vector3d normal;
  double offset;
  std::vector<int> loop;
  double area = 0.0;
};

// Puts a convex facet's vertices in counter-clockwise order about `n`.
void order_ccw(const std::vector<Vector3d>& points, const Vector3d& n, std::vector<int>* loop) {
  Vector3d c = Vector3d::Zero();
  for (int i : *loop) c += points[i];
  c /= static_cast<double>(loop->size());
  const Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  std::vector<std::pair<double, int>> by_angle;
  for (int i : *loop) by_angle.emplace_back(std::atan2(w.dot(points[i] - c), u.dot(points[i] - c)), i);
  std::sort(by_angle.begin(), by_angle.end());
  for (size_t k = 0; k < by_angle.size(); ++k) (*loop)[k] = by_angle[k].second;
}

// Runs Qhull; throws InputError with Qhull's own message on failure.
std::vector<Facet> qhull_facets(const std::vector<Vector3d>& points, const std::string& what) {
  std::vector<coordT> coords(3 * points.size());
  for (size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) coords[3 * i + k] = points[i][k];

  char* err_text = nullptr;
  size_t err_size = 0;
  FILE* err = open_memstream(&err_text, &err_size);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  QHULL_LIB_CHECK
  qh_zero(qh, err);
  // Default options: Qhull merges facets that are coplanar within its own
  // round-off, keeping each facet convex; we merge further below at our
  // tolerance.
  char cmd[] = "qhull";
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False, cmd, nullptr, err);
  std::vector<Facet> facets;
  if (code == 0) {
    facetT* facet;
    vertexT *vertex, **vertexp;
    FORALLfacets {
      Facet f;
      f.normal = Vector3d(facet->normal[0], facet->normal[1], facet->normal[2]);
      f.offset = -facet->offset;
      FOREACHvertex_(facet->vertices) f.loop.push_back(qh_pointid(qh, vertex->point));
      facets.push_back(std::move(f));
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(err);
  std::string message = err_text ? std::string(err_text, err_size) : std::string();
  std::free(err_text);
  if (code != 0) {
    const size_t start = message.find_first_not_of(" \n");
    const std::string first = start == std::string::npos ? "" : message.substr(start, message.find('\n', start) - start);
    throw InputError(fmt::format("{}: Qhull could not build the hull (exit code {}): {}", what, code, first));
  }
  for (Facet& f : facets) {
    order_ccw(points, f.normal, &f.loop);
    Vector3d twice = Vector3d::Zero();
    for (size_t k = 1; k + 1 < f.loop.size(); ++k)
      twice += (points[f.loop[k]] - points[f.loop[0]]).cross(points[f.loop[k + 1]] - points[f.loop[0]]);
    f.area = 0.5 * twice.norm();
  }
  return facets;
}

}  // namespace

ConvexShape ConvexShape::hull(const std::vector<Vector3d>& points, const std::string& what) {
  const int n = static_cast<int>(points.size());
  if (n < 4)
    throw InputError(fmt::format("{}: needs at least 4 points that are not coplanar, got {}", what, n));
  Eigen::AlignedBox3d box;
  for (int i = 0; i < n; ++i) {
    if (!points[i].allFinite()) throw InputError(fmt::format("{}: vertices[{}] is not finite", what, i));
    box.extend(points[i]);
  }
  const double tol = kRelTol * box.diagonal().norm();

  // Duplicates: sweep along x.
  {
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return points[a].x() < points[b].x(); });
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n && points[order[b]].x() - points[order[a]].x() <= tol; ++b)
        if ((points[order[a]] - points[order[b]]).norm() <= tol) {
          const int i = std::min(order[a], order[b]), j = std::max(order[a], order[b]);
          throw InputError(fmt::format("{}: duplicate points: {} and {} are closer than {:.3g} m", what,
                                       pt(points, i), pt(points, j), tol));
        }
  }

  // Collinear / coplanar: the farthest point from points[0], then from that
  // line, then from that plane.
  {
    int i1 = 1;
    for (int i = 1; i < n; ++i)
      if ((points[i] - points[0]).squaredNorm() > (points[i1] - points[0]).squaredNorm()) i1 = i;
    const Vector3d u = (points[i1] - points[0]).normalized();
    auto line_dist = [&](int i) {
      const Vector3d r = points[i] - points[0];
      return (r - r.dot(u) * u).norm();
    };
    int i2 = 0;
    for (int i = 0; i < n; ++i)
      if (line_dist(i) > line_dist(i2)) i2 = i;
    if (line_dist(i2) <= tol)
      throw InputError(fmt::format("{}: all {} points are collinear (on the line through vertices[0] and "
                                   "vertices[{}]); a body needs volume",
                                   what, n, i1));
    const Vector3d nrm = u.cross(points[i2] - points[0]).normalized();
    int i3 = 0;
    for (int i = 0; i < n; ++i)
      if (std::abs(nrm.dot(points[i] - points[0])) > std::abs(nrm.dot(points[i3] - points[0]))) i3 = i;
    const double thickness = std::abs(nrm.dot(points[i3] - points[0]));
    if (thickness <= tol)
      throw InputError(fmt::format("{}: all {} points are coplanar (within {:.3g} m of the plane through "
                                   "vertices[0], vertices[{}] and vertices[{}]); a body needs volume",
                                   what, n, thickness, i1, i2));
  }

  const std::vector<Facet> facets = qhull_facets(points, what);
  const int nf = static_cast<int>(facets.size());
  auto ambiguous = [&](const std::string& detail) {
    return InputError(fmt::format("{}: the hull is numerically ambiguous at tolerance {:.3g} m ({}): remove nearly "
                                  "coincident, collinear or coplanar points",
                                  what, tol, detail));
  };

  // Facet adjacency through directed edges: (a, b) in one facet's loop, (b, a)
  // in its neighbour's.
  std::map<std::pair<int, int>, int> edge_facet;
  for (int f = 0; f < nf; ++f) {
    const auto& loop = facets[f].loop;
    for (size_t k = 0; k < loop.size(); ++k)
      if (!edge_facet.emplace(std::make_pair(loop[k], loop[(k + 1) % loop.size()]), f).second)
        throw ambiguous("Qhull facets share a directed edge");
  }
  for (const auto& [e, f] : edge_facet)
    if (!edge_facet.count({e.second, e.first})) throw ambiguous("Qhull's hull is not closed");

  // Faces: grow regions of facets lying within tol of the plane of the
  // region's first (largest) facet, across shared edges.
  std::vector<int> by_area(nf);
  std::iota(by_area.begin(), by_area.end(), 0);
  std::stable_sort(by_area.begin(), by_area.end(), [&](int a, int b) { return facets[a].area > facets[b].area; });
  std::vector<int> region(nf, -1);
  std::vector<int> seed_of;  // region -> its seed facet
  for (int seed : by_area) {
    if (region[seed] >= 0) continue;
    const int r = static_cast<int>(seed_of.size());
    const Facet& plane = facets[seed];
    seed_of.push_back(seed);
    region[seed] = r;
    std::vector<int> stack = {seed};
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      const auto& loop = facets[f].loop;
      for (size_t k = 0; k < loop.size(); ++k) {
        const int g = edge_facet.at({loop[(k + 1) % loop.size()], loop[k]});
        if (region[g] >= 0) continue;
        bool flat = facets[g].normal.dot(plane.normal) > 0.0;
        for (int i : facets[g].loop) flat = flat && std::abs(plane.normal.dot(points[i]) - plane.offset) <= tol;
        if (!flat) continue;
        region[g] = r;
        stack.push_back(g);
      }
    }
  }

  // Each region's boundary: its facets' edges whose reverse lies in another
  // region, chained into one loop. A region whose boundary is not convex (a
  // facet left out in its middle) goes back to its separate Qhull facets,
  // which are convex: nearly coplanar faces are harmless, notched ones are not.
  std::vector<std::vector<int>> loops;
  for (;;) {
    const int nregions = static_cast<int>(seed_of.size());
    loops.assign(nregions, {});
    std::vector<std::map<int, int>> next(nregions);
    for (const auto& [e, f] : edge_facet)
      if (region[edge_facet.at({e.second, e.first})] != region[f])
        if (!next[region[f]].emplace(e.first, e.second).second) throw ambiguous("a face touches itself at a vertex");
    std::vector<int> notched;
    for (int r = 0; r < nregions; ++r) {
      if (next[r].empty()) throw ambiguous("a face has no boundary");
      const int start = next[r].begin()->first;
      int v = start;
      do {
        loops[r].push_back(v);
        auto it = next[r].find(v);
        if (it == next[r].end() || loops[r].size() > next[r].size()) throw ambiguous("a face boundary is open");
        v = it->second;
      } while (v != start);
      if (loops[r].size() != next[r].size()) throw ambiguous("a face has a hole");
      const Vector3d& nrm = facets[seed_of[r]].normal;
      const size_t m = loops[r].size();
      for (size_t k = 0; k < m; ++k) {
        const Vector3d& a = points[loops[r][k]];
        const Vector3d& b = points[loops[r][(k + 1) % m]];
        const Vector3d& c = points[loops[r][(k + 2) % m]];
        if ((b - a).cross(c - b).dot(nrm) / (c - a).norm() < -tol) {
          notched.push_back(r);
          break;
        }
      }
    }
    if (notched.empty()) break;
    for (int r : notched)
      for (int f = 0; f < nf; ++f)
        if (region[f] == r && f != seed_of[r]) {
          region[f] = static_cast<int>(seed_of.size());
          seed_of.push_back(f);
        }
  }

  // Corners: a point on the boundary of only two faces and within tol of the
  // chord of its neighbours in both loops lies on the edge between them: it is
  // not a corner. (A point of two faces that is not on such a chord stays a
  // vertex: a corner of a face folded at our tolerance.)
  {
    std::vector<std::vector<int>> faces_at(n);
    for (size_t r = 0; r < loops.size(); ++r)
      for (int i : loops[r]) faces_at[i].push_back(static_cast<int>(r));
    auto chord_distance = [&](const std::vector<int>& loop, int i) {
      const size_t m = loop.size();
      const size_t k = std::find(loop.begin(), loop.end(), i) - loop.begin();
      const Vector3d& a = points[loop[(k + m - 1) % m]];
      const Vector3d& c = points[loop[(k + 1) % m]];
      const Vector3d u = (c - a).normalized();
      const Vector3d r = points[i] - a;
      return (r - r.dot(u) * u).norm();
    };
    for (int i = 0; i < n; ++i) {
      if (faces_at[i].size() != 2) continue;
      auto& la = loops[faces_at[i][0]];
      auto& lb = loops[faces_at[i][1]];
      if (la.size() <= 3 || lb.size() <= 3 || chord_distance(la, i) > tol || chord_distance(lb, i) > tol) continue;
      la.erase(std::find(la.begin(), la.end(), i));
      lb.erase(std::find(lb.begin(), lb.end(), i));
    }
  }

  // Face planes: the normal of the region's seed facet, which Qhull made to
  // have every point on its inner side (a plane fitted to the corners of a
  // thin face could tilt).
  std::vector<Vector3d> normals;
  for (int seed : seed_of) normals.push_back(facets[seed].normal);

  // Vertices: the corners, in input order.
  std::vector<int> corners;
  for (const auto& loop : loops) corners.insert(corners.end(), loop.begin(), loop.end());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  std::vector<int> new_index(n, -1);
  std::vector<Vector3d> vertices;
  for (int i : corners) {
    new_index[i] = static_cast<int>(vertices.size());
    vertices.push_back(points[i]);
  }
  for (auto& loop : loops)
    for (int& i : loop) i = new_index[i];

  ConvexShape shape = [&] {
    try {
      return from_loops(vertices, loops, what, &normals);
    } catch (const InputError& e) {
      throw ambiguous(e.what());
    }
  }();
  shape.source_index_ = corners;

  // Say which points were dropped.
  std::vector<int> dropped;
  for (int i = 0; i < n; ++i)
    if (new_index[i] < 0) dropped.push_back(i);
  if (!dropped.empty()) {
    std::string list;
    const size_t shown = std::min<size_t>(dropped.size(), 20);
    for (size_t k = 0; k < shown; ++k) {
      const int i = dropped[k];
      const double s = shape.max_plane_distance(points[i]).value;
      list += fmt::format("{}vertices[{}] ({})", k ? ", " : "", i, s < -tol ? "inside" : "on the surface");
    }
    if (shown < dropped.size()) list += fmt::format(", ... ({} more)", dropped.size() - shown);
    shape.notes_.push_back(fmt::format("{}: {} of {} points are not corners of the convex hull and were dropped: {}",
                                       what, dropped.size(), n, list));
  }
  return shape;
}

}  // namespace freestand
