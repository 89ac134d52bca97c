#include "freestand/base_shape.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "freestand/input_error.h"

namespace freestand {

using Eigen::Vector3d;

void polygon_weights(const std::vector<Vector3d>& poly, const Vector3d& x, const Vector3d& n,
                     double tolerance, std::vector<double>* w) {
  const size_t m = poly.size();
  w->assign(m, 0.0);
  for (size_t i = 0; i < m; ++i)
    if ((poly[i] - x).norm() <= tolerance) {
      (*w)[i] = 1.0;
      return;
    }
  for (size_t i = 0; i < m; ++i) {
    const Vector3d e = poly[(i + 1) % m] - poly[i];
    const double t = (x - poly[i]).dot(e) / e.squaredNorm();
    if (t > 0.0 && t < 1.0 && (x - poly[i] - t * e).norm() <= tolerance) {
      (*w)[i] = 1.0 - t;
      (*w)[(i + 1) % m] = t;
      return;
    }
  }
  std::vector<double> r(m), tan_half(m);
  for (size_t i = 0; i < m; ++i) r[i] = (poly[i] - x).norm();
  for (size_t i = 0; i < m; ++i) {
    const Vector3d di = poly[i] - x, dj = poly[(i + 1) % m] - x;
    tan_half[i] = di.cross(dj).dot(n) / (r[i] * r[(i + 1) % m] + di.dot(dj));  // tan(alpha_i / 2)
  }
  double sum = 0.0;
  for (size_t i = 0; i < m; ++i) {
    (*w)[i] = (tan_half[(i + m - 1) % m] + tan_half[i]) / r[i];
    sum += (*w)[i];
  }
  for (double& v : *w) v /= sum;
}

namespace {

// The polygon with every edge moved inward by d: corner k is where the
// moved edges k - 1 and k meet. Throws when an edge would vanish or turn.
std::vector<Vector3d> inset_polygon(const std::vector<Vector3d>& p, const Vector3d& n, double d) {
  const size_t m = p.size();
  std::vector<Vector3d> along(m), on_line(m), out(m);
  for (size_t k = 0; k < m; ++k) {
    along[k] = (p[(k + 1) % m] - p[k]).normalized();
    on_line[k] = p[k] + d * n.cross(along[k]);  // n x edge points inward (counter-clockwise about n)
  }
  for (size_t k = 0; k < m; ++k) {
    const size_t j = (k + m - 1) % m;
    const double s = (on_line[k] - on_line[j]).cross(along[k]).dot(n) / along[j].cross(along[k]).dot(n);
    out[k] = on_line[j] + s * along[j];
  }
  for (size_t k = 0; k < m; ++k)
    if (!((out[(k + 1) % m] - out[k]).dot(along[k]) > 0.0))
      throw InputError(fmt::format("base: edge_inset {} m is too large for the base (an edge would vanish)", d));
  return out;
}

}  // namespace

BaseMap::BaseMap(const Clump& body, const BaseShape& shape) {
  const std::vector<FaceRef> base = body.base_faces();
  if (shape.edge_inset < 0.0 || !std::isfinite(shape.edge_inset))
    throw InputError(fmt::format("base: edge_inset must be >= 0, got {}", shape.edge_inset));
  if (shape.edge_inset > 0.0 && base.size() != 1)
    throw InputError(fmt::format("base: edge_inset needs a base of one face, this one has {}", base.size()));
  tolerance_ = 1e-9 * std::max(body.bounding_box().diagonal().norm(), 1.0);
  for (const FaceRef& ref : base) {
    const ConvexShape& piece = body.pieces()[ref.piece];
    const ShapeFace& face = piece.faces()[ref.face];
    Face f{face.normal, face.offset, {}, {}};
    for (int v : face.loop) f.corner.push_back(piece.vertices()[v]);
    f.target = shape.edge_inset > 0.0 ? inset_polygon(f.corner, f.normal, shape.edge_inset) : f.corner;
    faces_.push_back(std::move(f));
  }
  for (const CornerGap& gap : shape.corner_gaps) {
    if (!std::isfinite(gap.gap) || !gap.direction.allFinite() || gap.direction.norm() == 0.0)
      throw InputError("base: a corner gap needs a finite gap and a nonzero corner direction [x, y]");
    // The base corner farthest along the direction; a tie is ambiguous.
    double best = -1e300, second = -1e300;
    Vector3d chosen = Vector3d::Zero();
    for (const Face& f : faces_)
      for (const Vector3d& c : f.corner) {
        const double reach = gap.direction.dot(c.head<2>());
        if ((c - chosen).norm() <= tolerance_) continue;  // the same corner seen from another face
        if (reach > best) {
          second = best;
          best = reach;
          chosen = c;
        } else {
          second = std::max(second, reach);
        }
      }
    if (best - second <= tolerance_ * gap.direction.norm())
      throw InputError(fmt::format("base: corner [{}, {}] does not single out one base corner",
                                   gap.direction.x(), gap.direction.y()));
    for (Face& f : faces_)
      for (size_t k = 0; k < f.corner.size(); ++k)
        if ((f.corner[k] - chosen).norm() <= tolerance_) f.target[k] -= gap.gap * f.normal;
  }
}

Vector3d BaseMap::operator()(const Vector3d& p) const {
  std::vector<double> w;
  for (const Face& f : faces_) {
    if (std::abs(f.normal.dot(p) - f.offset) > tolerance_) continue;
    const size_t m = f.corner.size();
    bool inside = true;
    for (size_t k = 0; k < m && inside; ++k)
      inside = (f.corner[(k + 1) % m] - f.corner[k]).cross(p - f.corner[k]).dot(f.normal) >= -tolerance_ *
               (f.corner[(k + 1) % m] - f.corner[k]).norm();
    if (!inside) continue;
    polygon_weights(f.corner, p, f.normal, tolerance_, &w);
    Vector3d moved = Vector3d::Zero();
    for (size_t k = 0; k < m; ++k) moved += w[k] * f.target[k];
    return moved;
  }
  return p;
}

}  // namespace freestand
