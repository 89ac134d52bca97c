#include "freestand/shape_clump.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "freestand/input_error.h"

namespace freestand {

using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

constexpr double kRelTol = 1e-9;  // same as convex_shape.cpp

// Separating-axis test of two convex polyhedra. Returns the smallest overlap
// of their projections over the candidate axes (face normals of both, cross
// products of edge directions): <= 0 means separated or touching.
double sat_overlap(const ConvexShape& a, const ConvexShape& b, Vector3d* axis_out) {
  auto project = [](const ConvexShape& s, const Vector3d& axis, double* lo, double* hi) {
    *lo = std::numeric_limits<double>::infinity();
    *hi = -*lo;
    for (const Vector3d& v : s.vertices()) {
      const double p = axis.dot(v);
      *lo = std::min(*lo, p);
      *hi = std::max(*hi, p);
    }
  };
  double best = std::numeric_limits<double>::infinity();
  auto test = [&](const Vector3d& axis) {
    double alo, ahi, blo, bhi;
    project(a, axis, &alo, &ahi);
    project(b, axis, &blo, &bhi);
    const double overlap = std::min(ahi - blo, bhi - alo);
    if (overlap < best) {
      best = overlap;
      *axis_out = axis;
    }
  };
  for (const ShapeFace& f : a.faces()) test(f.normal);
  for (const ShapeFace& f : b.faces()) test(f.normal);
  for (const ShapeEdge& ea : a.edges()) {
    const Vector3d da = a.vertices()[ea.v1] - a.vertices()[ea.v0];
    for (const ShapeEdge& eb : b.edges()) {
      const Vector3d c = da.cross(b.vertices()[eb.v1] - b.vertices()[eb.v0]);
      const double n = c.norm();
      if (n > 1e-9 * da.norm() * (b.vertices()[eb.v1] - b.vertices()[eb.v0]).norm()) test(c / n);
    }
  }
  return best;
}

// Signed area of a 2-D polygon.
double area_2d(const std::vector<Vector2d>& p) {
  double a = 0.0;
  for (size_t k = 0; k < p.size(); ++k) {
    const Vector2d& q = p[k];
    const Vector2d& r = p[(k + 1) % p.size()];
    a += q.x() * r.y() - q.y() * r.x();
  }
  return 0.5 * a;
}

// Area of the intersection of two counter-clockwise convex polygons
// (Sutherland-Hodgman clipping of `subject` by each edge of `clip`).
double intersection_area(std::vector<Vector2d> subject, const std::vector<Vector2d>& clip) {
  for (size_t k = 0; k < clip.size() && !subject.empty(); ++k) {
    const Vector2d a = clip[k], b = clip[(k + 1) % clip.size()];
    auto side = [&](const Vector2d& p) { return (b - a).x() * (p - a).y() - (b - a).y() * (p - a).x(); };
    std::vector<Vector2d> out;
    for (size_t i = 0; i < subject.size(); ++i) {
      const Vector2d& p = subject[i];
      const Vector2d& q = subject[(i + 1) % subject.size()];
      const double sp = side(p), sq = side(q);
      if (sp >= 0) out.push_back(p);
      if ((sp >= 0) != (sq >= 0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
    subject = std::move(out);
  }
  return subject.size() >= 3 ? std::max(0.0, area_2d(subject)) : 0.0;
}

}  // namespace

MassProperties combine_mass_properties(const std::vector<MassProperties>& parts) {
  MassProperties total;
  for (const MassProperties& p : parts) {
    total.volume += p.volume;
    total.mass += p.mass;
    total.com += p.mass * p.com;
  }
  total.com /= total.mass;
  for (const MassProperties& p : parts) {
    const Vector3d r = p.com - total.com;
    total.inertia += p.inertia + p.mass * (r.squaredNorm() * Matrix3d::Identity() - r * r.transpose());
  }
  return total;
}

Clump::Clump(const ConvexShape& shape) {
  pieces_.push_back(shape);
  notes_ = shape.notes();
  tolerance_ = shape.tolerance();
  classify_faces("clump");
}

Clump::Clump(const std::vector<ClumpPiece>& pieces, const std::string& what) {
  if (pieces.empty()) throw InputError(what + ": needs at least one piece");
  Eigen::AlignedBox3d box;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const ClumpPiece& p = pieces[i];
    const double qn = p.orientation.coeffs().norm();
    if (!(std::abs(qn - 1.0) < 1e-6))
      throw InputError(fmt::format("{}: piece {}: the orientation quaternion must have unit norm, got {}", what, i, qn));
    try {
      pieces_.push_back(p.shape.transformed(p.orientation.normalized().toRotationMatrix(), p.offset));
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: piece {}: {}", what, i, e.what()));
    }
    for (const std::string& n : p.shape.notes()) notes_.push_back(fmt::format("{}: piece {}: {}", what, i, n));
    box.extend(pieces_.back().bounding_box());
  }
  tolerance_ = kRelTol * box.diagonal().norm();
  for (size_t i = 0; i < pieces_.size(); ++i)
    for (size_t j = i + 1; j < pieces_.size(); ++j) {
      Vector3d axis;
      const double overlap = sat_overlap(pieces_[i], pieces_[j], &axis);
      if (overlap > tolerance_)
        throw InputError(fmt::format("{}: pieces {} and {} overlap (by {:.6g} m along ({:.6g}, {:.6g}, {:.6g})); "
                                     "pieces may touch but not overlap, or their volume would count twice",
                                     what, i, j, overlap, axis.x(), axis.y(), axis.z()));
    }
  classify_faces(what);
}

void Clump::classify_faces(const std::string& what) {
  const size_t np = pieces_.size();
  cover_.assign(np, {});
  covered_fraction_.assign(np, {});
  open_faces_.assign(np, {});
  for (size_t i = 0; i < np; ++i) {
    const ConvexShape& a = pieces_[i];
    for (size_t f = 0; f < a.faces().size(); ++f) {
      const ShapeFace& fa = a.faces()[f];
      const Vector3d u = fa.normal.unitOrthogonal();
      const Vector3d w = fa.normal.cross(u);
      std::vector<Vector2d> pa;
      for (int v : fa.loop) pa.emplace_back(u.dot(a.vertices()[v]), w.dot(a.vertices()[v]));
      double covered = 0.0;
      for (size_t j = 0; j < np; ++j) {
        if (j == i) continue;
        const ConvexShape& b = pieces_[j];
        for (const ShapeFace& fb : b.faces()) {
          if (fa.normal.dot(fb.normal) > -1.0 + 1e-9 || std::abs(fa.offset + fb.offset) > tolerance_) continue;
          std::vector<Vector2d> pb;
          for (int v : fb.loop) pb.emplace_back(u.dot(b.vertices()[v]), w.dot(b.vertices()[v]));
          std::reverse(pb.begin(), pb.end());  // seen from fa's outside, fb's loop runs clockwise
          covered += intersection_area(pa, pb);
        }
      }
      const double fraction = std::min(1.0, covered / fa.area);
      FaceCover c = FaceCover::kExposed;
      if (fraction >= 1.0 - 1e-9) {
        c = FaceCover::kCovered;
      } else if (fraction > 1e-9) {
        c = FaceCover::kPartlyCovered;
        notes_.push_back(fmt::format("{}: piece {} face {}: {:.1f}% of its area lies against other pieces; "
                                     "its contact nodes there are kept",
                                     what, i, f, 100.0 * fraction));
      }
      cover_[i].push_back(c);
      covered_fraction_[i].push_back(fraction);
      if (c != FaceCover::kCovered) open_faces_[i].push_back(static_cast<int>(f));
    }
  }
}

double Clump::volume() const {
  double v = 0.0;
  for (const ConvexShape& p : pieces_) v += p.volume();
  return v;
}

MassProperties Clump::mass_properties(double density) const {
  return mass_properties(std::vector<double>(pieces_.size(), density));
}

MassProperties Clump::mass_properties(const std::vector<double>& densities) const {
  if (densities.size() != pieces_.size())
    throw InputError(fmt::format("clump: {} densities given for {} pieces", densities.size(), pieces_.size()));
  std::vector<MassProperties> parts;
  for (size_t i = 0; i < pieces_.size(); ++i) parts.push_back(pieces_[i].mass_properties(densities[i]));
  return combine_mass_properties(parts);
}

Eigen::AlignedBox3d Clump::bounding_box() const {
  Eigen::AlignedBox3d box;
  for (const ConvexShape& p : pieces_) box.extend(p.bounding_box());
  return box;
}

double Clump::bounding_radius(const Vector3d& centre) const {
  double r = 0.0;
  for (const ConvexShape& p : pieces_) r = std::max(r, p.bounding_radius(centre));
  return r;
}

std::vector<FaceRef> Clump::level_faces(double up) const {
  const double level = up > 0.0 ? bounding_box().max().z() : bounding_box().min().z();
  std::vector<FaceRef> out;
  for (size_t i = 0; i < pieces_.size(); ++i)
    for (size_t f = 0; f < pieces_[i].faces().size(); ++f) {
      const ShapeFace& face = pieces_[i].faces()[f];
      if (face.normal.z() * up > 0.0 && std::hypot(face.normal.x(), face.normal.y()) <= 1e-9) {
        if (std::abs(face.offset - up * level) <= tolerance_ && cover_[i][f] != FaceCover::kCovered)
          out.push_back({static_cast<int>(i), static_cast<int>(f)});
      }
    }
  return out;
}

std::vector<FaceRef> Clump::base_faces() const { return level_faces(-1.0); }

std::vector<FaceRef> Clump::bearing_faces() const {
  std::vector<FaceRef> out = level_faces(-1.0);
  for (const FaceRef& f : level_faces(1.0)) out.push_back(f);
  return out;
}

ClumpDistance Clump::signed_distance(const Vector3d& x) const {
  ClumpDistance out;
  // Inside some piece?
  double deepest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < pieces_.size(); ++i) {
    const ConvexShape& p = pieces_[i];
    if (!(p.max_plane_distance(x).value <= 0.0)) continue;  // outside (or a NaN point)
    double value = -std::numeric_limits<double>::infinity();
    int face = -1;
    for (int f : open_faces_[i]) {
      const ShapeFace& sf = p.faces()[f];
      const double s = sf.normal.dot(x) - sf.offset;
      if (s > value) {
        value = s;
        face = f;
      }
    }
    if (value < deepest) {
      deepest = value;
      out.piece = static_cast<int>(i);
      out.surface.distance = value;
      out.surface.face = face;
      out.surface.normal = p.faces()[face].normal;
      out.surface.point = x - value * out.surface.normal;
      out.surface.feature = SurfaceFeature::kFace;
      out.surface.feature_index = face;
    }
  }
  if (out.piece >= 0) return out;
  // Outside all: the nearest piece.
  for (size_t i = 0; i < pieces_.size(); ++i) {
    const SurfaceDistance d = pieces_[i].signed_distance(x);
    if (out.piece < 0 || d.distance < out.surface.distance) {
      out.surface = d;
      out.piece = static_cast<int>(i);
    }
  }
  return out;
}

}  // namespace freestand
