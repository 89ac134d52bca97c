// Convex shapes: construction (box, prism, Qhull hull), mass properties
// against closed forms, and the contact queries (signed distance, normal,
// bounds), plus the errors users get for bad input.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "freestand/convex_shape.h"
#include "freestand/input_error.h"

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using freestand::ConvexShape;
using freestand::InputError;
using freestand::MassProperties;
using freestand::SurfaceFeature;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Mass properties are sums of a few hundred products of O(1) numbers: the
// round-off is ~1e-15 relative. 1e-12 passes any correct formula and fails
// any wrong term (a missing 1/12, a wrong sign, a parallel-axis slip each
// change a value by more than 1e-3).
constexpr double kMassTol = 1e-12;

// Geometry checks on coordinates of size ~1 m: round-off ~1e-15 m.
constexpr double kGeomTol = 1e-12;

void expect_matrix_near(const Matrix3d& a, const Matrix3d& b, double rel, const std::string& what) {
  const double scale = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff());
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), rel * scale) << what << "\n" << a << "\nvs\n" << b;
}

// Largest relative error: volume, |com error| / size, inertia entries / largest entry.
double mass_error(const MassProperties& got, const MassProperties& want) {
  const double size = std::cbrt(want.volume);
  return std::max({std::abs(got.volume - want.volume) / want.volume, std::abs(got.mass - want.mass) / want.mass,
                   (got.com - want.com).norm() / size,
                   (got.inertia - want.inertia).cwiseAbs().maxCoeff() / want.inertia.cwiseAbs().maxCoeff()});
}

void expect_mass_near(const MassProperties& got, const MassProperties& want, const std::string& what) {
  std::printf("[measured] mass properties, %s: largest relative error %.1e\n", what.c_str(), mass_error(got, want));
  EXPECT_NEAR(got.volume, want.volume, kMassTol * want.volume) << what;
  EXPECT_NEAR(got.mass, want.mass, kMassTol * want.mass) << what;
  const double size = std::cbrt(want.volume);
  EXPECT_LE((got.com - want.com).norm(), kMassTol * size) << what << " com " << got.com.transpose();
  expect_matrix_near(got.inertia, want.inertia, kMassTol, what + " inertia");
}

// Properties every shape must have: loops counter-clockwise seen from outside
// (their Newell normal is the face normal), vertices on their face plane and
// inside every plane, Euler's formula, each edge's two faces holding it.
// `rel`: allowed distance of a vertex from its face plane, relative to the
// bounding-box diagonal (round-off for exact input; the input's own
// non-planarity for deliberately perturbed input).
void check_polytope(const ConvexShape& s, const std::string& what, double rel = 1e-12) {
  const auto& v = s.vertices();
  const double tol = rel * s.bounding_box().diagonal().norm();
  for (size_t f = 0; f < s.faces().size(); ++f) {
    const auto& face = s.faces()[f];
    Vector3d newell = Vector3d::Zero();
    for (size_t k = 0; k < face.loop.size(); ++k)
      newell += v[face.loop[k]].cross(v[face.loop[(k + 1) % face.loop.size()]]);
    EXPECT_GT(newell.dot(face.normal), 0.0) << what << " face " << f;
    if (rel <= 1e-12) {  // exact input: the plane is the loop's own plane
      EXPECT_NEAR(newell.normalized().dot(face.normal), 1.0, 1e-12) << what << " face " << f;
      EXPECT_NEAR(0.5 * newell.norm(), face.area, 1e-12 * face.area) << what << " face " << f;
    }
    EXPECT_NEAR(face.normal.norm(), 1.0, 1e-14);
    for (int i : face.loop) EXPECT_NEAR(face.normal.dot(v[i]), face.offset, tol) << what << " face " << f;
    for (size_t i = 0; i < v.size(); ++i) EXPECT_LE(face.normal.dot(v[i]) - face.offset, tol) << what;
  }
  EXPECT_EQ(static_cast<int>(v.size()) - static_cast<int>(s.edges().size()) + static_cast<int>(s.faces().size()), 2)
      << what;
  for (const auto& e : s.edges()) {
    for (int f : {e.left, e.right}) {
      const auto& loop = s.faces()[f].loop;
      EXPECT_NE(std::find(loop.begin(), loop.end(), e.v0), loop.end()) << what;
      EXPECT_NE(std::find(loop.begin(), loop.end(), e.v1), loop.end()) << what;
    }
  }
  // Volume by an independent route: pyramids from the origin over each face,
  // V = sum d_f A_f / 3.
  double volume = 0.0;
  for (const auto& face : s.faces()) volume += face.offset * face.area / 3.0;
  EXPECT_NEAR(volume, s.volume(), 10 * rel * s.volume()) << what;
}

// Closed form of a right prism on a regular n-gon of circumradius r, height h.
MassProperties prism_closed_form(double r, int n, double h, double rho) {
  const double t = 2.0 * kPi / n;
  MassProperties m;
  m.volume = 0.5 * n * r * r * std::sin(t) * h;
  m.mass = rho * m.volume;
  m.com = Vector3d(0, 0, h / 2);
  // Second area moment of the n-gon about a centroidal axis in its plane:
  // A r^2 (2 + cos(2 pi / n)) / 12 (the same for every direction, n >= 3).
  const double k = r * r * (2.0 + std::cos(t)) / 12.0;
  m.inertia = Vector3d(m.mass * (k + h * h / 12.0), m.mass * (k + h * h / 12.0), 2.0 * m.mass * k).asDiagonal();
  return m;
}

// Tonon (2004), J. Math. Stat. 1(1): inertia of a tetrahedron about its
// centroid from explicit polynomial formulas in the vertex coordinates.
MassProperties tonon_tetrahedron(const std::vector<Vector3d>& p, double rho) {
  const Vector3d c = (p[0] + p[1] + p[2] + p[3]) / 4.0;
  std::vector<Vector3d> q;
  for (const Vector3d& x : p) q.push_back(x - c);
  const double det = std::abs((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])));
  auto sq = [&](int a) {  // sum_{i <= j} q_i,a q_j,a
    double s = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j) s += q[i][a] * q[j][a];
    return s;
  };
  auto prod = [&](int a, int b) {  // 2 sum_i q_i,a q_i,b + sum_{i != j} q_i,a q_j,b
    double s = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) s += (i == j ? 2.0 : 1.0) * q[i][a] * q[j][b];
    return s;
  };
  const double a = rho * det * (sq(1) + sq(2)) / 60.0;
  const double b = rho * det * (sq(0) + sq(2)) / 60.0;
  const double cc = rho * det * (sq(0) + sq(1)) / 60.0;
  const double ap = rho * det * prod(1, 2) / 120.0;
  const double bp = rho * det * prod(0, 2) / 120.0;
  const double cp = rho * det * prod(0, 1) / 120.0;
  MassProperties m;
  m.volume = det / 6.0;
  m.mass = rho * m.volume;
  m.com = c;
  m.inertia << a, -cp, -bp, -cp, b, -ap, -bp, -ap, cc;
  return m;
}

std::vector<Vector3d> cube_corners(double s) {
  std::vector<Vector3d> p;
  for (int i = 0; i < 8; ++i) p.emplace_back((i & 1) ? s : -s, (i & 2) ? s : -s, (i & 4) ? 2 * s : 0.0);
  return p;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

}  // namespace

// ---------------------------------------------------------------------------
TEST(ConvexBox, FacesVerticesEdgesAndFrame) {
  const ConvexShape b = ConvexShape::box(Vector3d(0.3, 0.2, 0.5));
  EXPECT_EQ(b.vertices().size(), 8u);
  EXPECT_EQ(b.faces().size(), 6u);
  EXPECT_EQ(b.edges().size(), 12u);
  // Documented face order: base, top, -y, +x, +y, -x.
  const std::vector<Vector3d> normals = {-Vector3d::UnitZ(), Vector3d::UnitZ(), -Vector3d::UnitY(),
                                         Vector3d::UnitX(),  Vector3d::UnitY(), -Vector3d::UnitX()};
  const std::vector<double> offsets = {0.0, 1.0, 0.2, 0.3, 0.2, 0.3};
  for (int f = 0; f < 6; ++f) {
    EXPECT_LE((b.faces()[f].normal - normals[f]).norm(), kGeomTol) << f;
    EXPECT_NEAR(b.faces()[f].offset, offsets[f], kGeomTol) << f;
    EXPECT_EQ(b.faces()[f].loop.size(), 4u);
  }
  EXPECT_NEAR(b.faces()[0].area, 0.6 * 0.4, kGeomTol);
  EXPECT_LE((b.faces()[0].centroid - Vector3d::Zero()).norm(), kGeomTol);  // origin: base-face centre
  EXPECT_LE((b.bounding_box().min() - Vector3d(-0.3, -0.2, 0)).norm(), kGeomTol);
  EXPECT_LE((b.bounding_box().max() - Vector3d(0.3, 0.2, 1.0)).norm(), kGeomTol);
  EXPECT_NEAR(b.bounding_radius(Vector3d(0, 0, 0.5)), std::sqrt(0.09 + 0.04 + 0.25), kGeomTol);
  check_polytope(b, "box");
}

TEST(ConvexHull, CubeWithInteriorAndSurfacePointsHasSixFacesEightVertices) {
  std::vector<Vector3d> p = cube_corners(0.5);
  p.insert(p.begin() + 3, Vector3d(0.1, -0.2, 0.3));  // inside
  p.emplace_back(0.0, 0.0, 0.5);                      // centre
  p.emplace_back(0.5, 0.0, 0.5);                      // centre of the +x face
  p.emplace_back(0.5, 0.5, 0.5);                      // midpoint of a vertical edge
  p.emplace_back(-0.2, 0.3, 0.0);                     // on the base
  const ConvexShape s = ConvexShape::hull(p);
  EXPECT_EQ(s.vertices().size(), 8u);
  EXPECT_EQ(s.faces().size(), 6u);
  EXPECT_EQ(s.edges().size(), 12u);
  for (const auto& f : s.faces()) EXPECT_EQ(f.loop.size(), 4u);
  // Vertices keep the input order; source_index maps back to the input.
  const std::vector<int> expect_source = {0, 1, 2, 4, 5, 6, 7, 8};
  EXPECT_EQ(s.source_index(), expect_source);
  for (size_t i = 0; i < s.vertices().size(); ++i) EXPECT_EQ(s.vertices()[i], p[s.source_index()[i]]);
  ASSERT_EQ(s.notes().size(), 1u);
  EXPECT_NE(s.notes()[0].find("5 of 13 points are not corners"), std::string::npos) << s.notes()[0];
  EXPECT_NE(s.notes()[0].find("vertices[3] (inside)"), std::string::npos) << s.notes()[0];
  EXPECT_NE(s.notes()[0].find("vertices[11] (on the surface)"), std::string::npos) << s.notes()[0];
  EXPECT_NEAR(s.volume(), 1.0, 1e-14);
  check_polytope(s, "cube hull");
  expect_mass_near(s.mass_properties(2.0), ConvexShape::box(Vector3d(0.5, 0.5, 0.5)).mass_properties(2.0),
                   "cube hull vs box");
}

TEST(ConvexHull, FacetsCoplanarWithinToleranceAreOneFace) {
  // Qhull merges only facets coplanar within round-off (~1e-15 m here). A top
  // corner raised by 1e-11 m, a point 1e-11 m outside the middle of a face and
  // another 1e-11 m outside the middle of an edge make Qhull fold the top and
  // keep the extra points as vertices; at our tolerance (1e-9 x diagonal =
  // 1.7e-9 m) the top is one face and the extra points are not corners.
  std::vector<Vector3d> p = cube_corners(0.5);
  p[7].z() += 1e-11;
  p.emplace_back(0.5 + 1e-11, 0.1, 0.4);                    // +x face
  p.emplace_back(0.5 + 1e-11, -0.5 - 1e-11, 0.5);           // +x/-y edge
  const ConvexShape s = ConvexShape::hull(p);
  EXPECT_EQ(s.faces().size(), 6u);
  EXPECT_EQ(s.vertices().size(), 8u);
  ASSERT_EQ(s.notes().size(), 1u);
  EXPECT_NE(s.notes()[0].find("vertices[8] (on the surface), vertices[9] (on the surface)"), std::string::npos)
      << s.notes()[0];
  check_polytope(s, "nearly flat top", 1e-9);  // the top is 1e-11 m from flat
  // The same fold 1e-6 m high is real: the top becomes two triangles.
  p = cube_corners(0.5);
  p[7].z() += 1e-6;
  const ConvexShape folded = ConvexShape::hull(p);
  EXPECT_EQ(folded.faces().size(), 7u);
  check_polytope(folded, "folded top");
}

TEST(ConvexHull, DrumFromPointsMergesCoplanarFacetsIntoCaps) {
  // Each 24-gon cap must be one face however Qhull splits it into facets;
  // the result must equal the built-in prism.
  const ConvexShape drum = ConvexShape::prism(0.4, 24, 0.7);
  std::vector<Vector3d> p = drum.vertices();
  std::shuffle(p.begin(), p.end(), std::mt19937(3));
  const ConvexShape s = ConvexShape::hull(p);
  EXPECT_EQ(s.faces().size(), 26u);
  EXPECT_EQ(s.vertices().size(), 48u);
  EXPECT_EQ(s.edges().size(), 72u);
  EXPECT_TRUE(s.notes().empty());
  check_polytope(s, "drum hull");
  expect_mass_near(s.mass_properties(2500), drum.mass_properties(2500), "drum hull vs prism");
}

TEST(ConvexHull, RandomPointsGiveAValidPolytope) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vector3d> p;
  for (int i = 0; i < 300; ++i) p.push_back(Vector3d(g(rng), g(rng), g(rng)) * 0.3 + Vector3d(0, 0, 1));
  const ConvexShape s = ConvexShape::hull(p);
  check_polytope(s, "random hull");
  for (const Vector3d& x : p) EXPECT_LE(s.max_plane_distance(x).value, s.tolerance());
  EXPECT_EQ(s.notes().size(), 1u);
  // Every facet of random points is a triangle.
  for (const auto& f : s.faces()) EXPECT_EQ(f.loop.size(), 3u);
}

TEST(ConvexHull, DegenerateScansOfBoxesAndDrumsInAnyOrientation) {
  // Scan-like input full of coplanar and collinear points (a grid on every
  // face of a box, rings of points on a drum's caps and side lines), jittered
  // by 1e-13 m and rotated: the hull must still be the box / the prism.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1e-13, 1e-13);
  for (int trial = 0; trial < 6; ++trial) {
    const Matrix3d R = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    std::vector<Vector3d> box_pts, drum_pts;
    for (int i = 0; i <= 6; ++i)
      for (int j = 0; j <= 6; ++j)
        for (int k = 0; k <= 6; ++k)
          if (i == 0 || i == 6 || j == 0 || j == 6 || k == 0 || k == 6)
            box_pts.emplace_back(-0.3 + 0.1 * i, -0.6 + 0.2 * j, 0.25 * k);
    const ConvexShape drum = ConvexShape::prism(0.5, 16, 0.8);
    for (int k = 0; k < 16; ++k)
      for (int s = 0; s < 4; ++s) {
        const Vector3d a = drum.vertices()[k], b = drum.vertices()[(k + 1) % 16];
        for (double z : {0.0, 0.2, 0.8}) drum_pts.push_back(a + s / 4.0 * (b - a) + Vector3d(0, 0, z));
      }
    drum_pts.emplace_back(0, 0, 0.4);
    for (auto* pts : {&box_pts, &drum_pts})
      for (Vector3d& p : *pts) p = R * p + Vector3d(jitter(rng), jitter(rng), jitter(rng));
    const ConvexShape b = ConvexShape::hull(box_pts);
    EXPECT_EQ(b.faces().size(), 6u) << trial;
    EXPECT_EQ(b.vertices().size(), 8u) << trial;
    EXPECT_NEAR(b.volume(), 0.6 * 1.2 * 1.5, 1e-12) << trial;
    check_polytope(b, "box scan", 1e-9);
    const ConvexShape d = ConvexShape::hull(drum_pts);
    EXPECT_EQ(d.faces().size(), 18u) << trial;
    EXPECT_EQ(d.vertices().size(), 32u) << trial;
    EXPECT_NEAR(d.volume(), drum.volume(), 1e-12) << trial;
    check_polytope(d, "drum scan", 1e-9);
  }
}

TEST(ConvexHull, PointsJitteredAtTheToleranceStillGiveAHull) {
  // The hardest case for merging: grids on a box's faces jittered by about
  // the tolerance itself, so some facets merge and their neighbours do not
  // (faces that would be notched are kept as Qhull's separate facets). Every
  // input point must end within 10 tolerances of the hull, the documented
  // guarantee.
  for (int seed = 0; seed < 60; ++seed) {
    std::mt19937 rng(seed);
    const Matrix3d R = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    std::uniform_real_distribution<double> jitter(-3e-9, 3e-9);
    const int n = 2 + seed % 5;
    std::vector<Vector3d> p;
    for (int a = 0; a <= n; ++a)
      for (int b = 0; b <= n; ++b)
        for (int c = 0; c <= n; ++c)
          if (a == 0 || a == n || b == 0 || b == n || c == 0 || c == n)
            p.push_back(R * Vector3d(a / double(n), 0.5 * b / n, 2.0 * c / n) +
                        Vector3d(jitter(rng), jitter(rng), jitter(rng)));
    const ConvexShape s = ConvexShape::hull(p);
    double worst = 0;
    for (const Vector3d& x : p) worst = std::max(worst, s.max_plane_distance(x).value);
    EXPECT_LE(worst, 10 * s.tolerance()) << seed;
    EXPECT_NEAR(s.volume(), 1.0, 1e-7) << seed;
    check_polytope(s, "jittered box " + std::to_string(seed), 1e-8);
  }
}

TEST(ConvexPrism, FaceVertexEdgeCountsAndOrientation) {
  for (int n : {3, 4, 5, 6, 8, 13, 24, 100}) {
    const ConvexShape s = ConvexShape::prism(0.5, n, 1.2);
    EXPECT_EQ(s.faces().size(), static_cast<size_t>(n + 2)) << n;
    EXPECT_EQ(s.vertices().size(), static_cast<size_t>(2 * n)) << n;
    EXPECT_EQ(s.edges().size(), static_cast<size_t>(3 * n)) << n;
    // First vertex at angle pi/n from +x; side face 2 + k faces 2 (k + 1) pi / n.
    EXPECT_NEAR(std::atan2(s.vertices()[0].y(), s.vertices()[0].x()), kPi / n, 1e-14) << n;
    EXPECT_NEAR(s.vertices()[0].norm(), 0.5, 1e-15);
    for (int k = 0; k < n; ++k) {
      const double t = 2.0 * (k + 1) * kPi / n;
      EXPECT_LE((s.faces()[2 + k].normal - Vector3d(std::cos(t), std::sin(t), 0)).norm(), 1e-14) << n << " " << k;
    }
    EXPECT_LE((s.faces()[2 + n - 1].normal - Vector3d::UnitX()).norm(), 1e-14);  // last side faces +x
    EXPECT_LE((s.faces()[0].normal + Vector3d::UnitZ()).norm(), 1e-15);
    EXPECT_NEAR(s.faces()[0].offset, 0.0, 1e-15);
    EXPECT_NEAR(s.faces()[1].offset, 1.2, 1e-15);
    check_polytope(s, "prism " + std::to_string(n));
  }
}

TEST(ConvexPrism, FourSidedPrismIsTheBox) {
  const double r = 0.7, h = 1.1;
  const ConvexShape p = ConvexShape::prism(r, 4, h);
  const ConvexShape b = ConvexShape::box(Vector3d(r / std::sqrt(2.0), r / std::sqrt(2.0), h / 2));
  expect_mass_near(p.mass_properties(1000), b.mass_properties(1000), "4-prism vs box");
  EXPECT_LE((p.bounding_box().min() - b.bounding_box().min()).norm(), 1e-15);
  EXPECT_LE((p.bounding_box().max() - b.bounding_box().max()).norm(), 1e-15);
}

// ---------------------------------------------------------------------------
TEST(ConvexMass, BoxClosedForm) {
  const double a = 0.3, b = 0.2, c = 0.9, rho = 2400;
  MassProperties want;
  want.volume = 8 * a * b * c;
  want.mass = rho * want.volume;
  want.com = Vector3d(0, 0, c);
  want.inertia = Vector3d(want.mass * (b * b + c * c) / 3, want.mass * (a * a + c * c) / 3,
                          want.mass * (a * a + b * b) / 3)
                     .asDiagonal();
  expect_mass_near(ConvexShape::box(Vector3d(a, b, c)).mass_properties(rho), want, "box");
}

TEST(ConvexMass, RegularPrismClosedForm) {
  for (int n : {3, 4, 5, 7, 12, 20, 64}) {
    const double r = 0.45, h = 0.8, rho = 2650;
    expect_mass_near(ConvexShape::prism(r, n, h).mass_properties(rho), prism_closed_form(r, n, h, rho),
                     "prism " + std::to_string(n));
  }
}

TEST(ConvexMass, RightTetrahedronTextbook) {
  // Vertices 0, a e_x, b e_y, c e_z: V = abc/6, COM (a, b, c)/4,
  // I_xx = 3 m (b^2 + c^2)/80, I_xy = m a b / 80 (products of inertia enter
  // the tensor with a minus sign: I_xy = -int x y dm, centred: +m a b/80).
  const double a = 0.6, b = 0.4, c = 1.0, rho = 7850;
  const ConvexShape s = ConvexShape::hull({{0, 0, 0}, {a, 0, 0}, {0, b, 0}, {0, 0, c}});
  MassProperties want;
  want.volume = a * b * c / 6;
  want.mass = rho * want.volume;
  want.com = Vector3d(a, b, c) / 4;
  const double m = want.mass;
  want.inertia << 3 * m * (b * b + c * c) / 80, m * a * b / 80, m * a * c / 80,  //
      m * a * b / 80, 3 * m * (a * a + c * c) / 80, m * b * c / 80,              //
      m * a * c / 80, m * b * c / 80, 3 * m * (a * a + b * b) / 80;
  expect_mass_near(s.mass_properties(rho), want, "right tetrahedron");
  EXPECT_EQ(s.faces().size(), 4u);
  check_polytope(s, "right tetrahedron");
}

TEST(ConvexMass, GeneralTetrahedronAgainstTonon) {
  // Tonon's worked example (J. Math. Stat. 2004): vertices (8.33220, -11.86875,
  // 0.93355), (0.75523, 5.00000, 16.37072), (52.61236, 5.00000, -5.38580),
  // (2.00000, 5.00000, 3.00000), density 1: a = 43520.33257, b = 194711.28938,
  // c = 191168.76173, a' = 4417.66150, b' = -46343.16662, c' = 11996.20119.
  const std::vector<Vector3d> p = {{8.33220, -11.86875, 0.93355},
                                   {0.75523, 5.00000, 16.37072},
                                   {52.61236, 5.00000, -5.38580},
                                   {2.00000, 5.00000, 3.00000}};
  const MassProperties got = ConvexShape::hull(p).mass_properties(1.0);
  expect_mass_near(got, tonon_tetrahedron(p, 1.0), "Tonon tetrahedron");
  // The published values (10 significant digits), to 1e-6 of the largest.
  EXPECT_NEAR(got.inertia(0, 0), 43520.33257, 1e-6 * 43520);
  EXPECT_NEAR(got.inertia(1, 1), 194711.28938, 1e-6 * 194711);
  EXPECT_NEAR(got.inertia(2, 2), 191168.76173, 1e-6 * 191168);
  EXPECT_NEAR(-got.inertia(1, 2), 4417.66150, 1e-6 * 194711);
  EXPECT_NEAR(-got.inertia(0, 2), -46343.16662, 1e-6 * 194711);
  EXPECT_NEAR(-got.inertia(0, 1), 11996.20119, 1e-6 * 194711);
  EXPECT_NEAR(got.com.x(), 15.92492, 5e-5);  // the paper rounds 15.9249475 down
  EXPECT_NEAR(got.com.y(), 0.78281, 1e-5);
  EXPECT_NEAR(got.com.z(), 3.72962, 1e-5);
}

TEST(ConvexMass, PlacementRotatesAndShiftsInertia) {
  const ConvexShape b = ConvexShape::prism(0.5, 7, 0.6);
  const Matrix3d R = (AngleAxisd(0.3, Vector3d(1, 2, 3).normalized()) * AngleAxisd(1.1, Vector3d::UnitX()))
                         .toRotationMatrix();
  const Vector3d t(0.2, -0.7, 0.4);
  const MassProperties m0 = b.mass_properties(900);
  MassProperties want = m0;
  want.com = R * m0.com + t;
  want.inertia = R * m0.inertia * R.transpose();
  expect_mass_near(b.transformed(R, t).mass_properties(900), want, "placed prism");
  check_polytope(b.transformed(R, t), "placed prism");
}

// ---------------------------------------------------------------------------
TEST(ConvexQuery, InsidePointsGiveDepthAndLeastPenetrationFace) {
  const ConvexShape b = ConvexShape::box(Vector3d(0.5, 0.3, 1.0));  // x +-0.5, y +-0.3, z 0..2
  struct Case {
    Vector3d x;
    double distance;
    int face;
  };
  const std::vector<Case> cases = {
      {{0.0, 0.0, 0.01}, -0.01, 0},    // just above the base
      {{0.0, 0.0, 1.95}, -0.05, 1},    // below the top
      {{0.45, 0.0, 1.0}, -0.05, 3},    // near +x
      {{0.1, -0.28, 1.0}, -0.02, 2},   // near -y
      {{0.49, 0.29, 1.0}, -0.01, 3},   // near the +x/+y edge: +x is closer
      {{0.48, 0.29, 1.0}, -0.01, 4},   // ... now +y is closer
      {{0.0, 0.0, 1.0}, -0.3, 2},      // centre: tie between -y and +y, the first wins
  };
  for (const Case& c : cases) {
    const auto d = b.signed_distance(c.x);
    EXPECT_NEAR(d.distance, c.distance, kGeomTol) << c.x.transpose();
    EXPECT_EQ(d.face, c.face) << c.x.transpose();
    EXPECT_EQ(d.feature, SurfaceFeature::kFace);
    EXPECT_LE((d.normal - b.faces()[c.face].normal).norm(), 0.0);
    EXPECT_LE((d.point - (c.x - c.distance * d.normal)).norm(), kGeomTol);
    EXPECT_NEAR(b.max_plane_distance(c.x).value, c.distance, kGeomTol);
    EXPECT_EQ(b.max_plane_distance(c.x).face, c.face);
  }
}

TEST(ConvexQuery, OutsidePointsNearFacesEdgesAndVertices) {
  const ConvexShape b = ConvexShape::box(Vector3d(0.5, 0.3, 1.0));
  // Face region: straight above the top.
  auto d = b.signed_distance(Vector3d(0.2, 0.1, 2.03));
  EXPECT_NEAR(d.distance, 0.03, kGeomTol);
  EXPECT_EQ(d.feature, SurfaceFeature::kFace);
  EXPECT_EQ(d.face, 1);
  EXPECT_LE((d.normal - Vector3d::UnitZ()).norm(), kGeomTol);
  // Edge region: beyond the +x/top edge, 3-4-5 triangle.
  d = b.signed_distance(Vector3d(0.5 + 0.03, 0.1, 2.0 + 0.04));
  EXPECT_NEAR(d.distance, 0.05, kGeomTol);
  EXPECT_EQ(d.feature, SurfaceFeature::kEdge);
  const auto& e = b.edges()[d.feature_index];
  EXPECT_TRUE((e.left == 1 && e.right == 3) || (e.left == 3 && e.right == 1));
  EXPECT_LE((d.normal - Vector3d(0.6, 0, 0.8)).norm(), kGeomTol);
  EXPECT_LE((d.point - Vector3d(0.5, 0.1, 2.0)).norm(), kGeomTol);
  // The cheap plane value underestimates there (0.04 < 0.05): documented.
  EXPECT_NEAR(b.max_plane_distance(Vector3d(0.53, 0.1, 2.04)).value, 0.04, kGeomTol);
  // Vertex region: beyond the (-0.5, -0.3, 0) corner.
  d = b.signed_distance(Vector3d(-0.5 - 0.02, -0.3 - 0.03, -0.06));
  EXPECT_NEAR(d.distance, 0.07, kGeomTol);
  EXPECT_EQ(d.feature, SurfaceFeature::kVertex);
  EXPECT_LE((b.vertices()[d.feature_index] - Vector3d(-0.5, -0.3, 0)).norm(), 0.0);
  EXPECT_LE((d.normal - Vector3d(-2, -3, -6) / 7.0).norm(), kGeomTol);
  // On the surface: distance 0, inside branch.
  d = b.signed_distance(Vector3d(0.5, 0.0, 1.0));
  EXPECT_EQ(d.distance, 0.0);
  EXPECT_EQ(d.face, 3);
  // A NaN point (a body that blew up) gives NaN, not a crash.
  EXPECT_TRUE(std::isnan(b.signed_distance(Vector3d(NAN, 0, 0)).distance));
  EXPECT_TRUE(std::isnan(b.max_plane_distance(Vector3d(0, NAN, 0)).value));
}

TEST(ConvexQuery, RandomPointsSatisfyTheProjectionConditions) {
  // For a convex polytope P = conv(vertices), p is the closest point of P to
  // an outside x iff p is in P and (x - p).(y - p) <= 0 for every vertex y.
  // For an inside x, the depth is min_f (d_f - n_f.x) and no face is closer.
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vector3d> pts;
  for (int i = 0; i < 40; ++i) pts.push_back(Vector3d(g(rng), g(rng), 0.5 * g(rng)));
  for (const ConvexShape& s : {ConvexShape::hull(pts), ConvexShape::prism(0.8, 9, 1.5)}) {
    const Eigen::AlignedBox3d box = s.bounding_box();
    std::uniform_real_distribution<double> u(-0.3, 1.3);
    int outside = 0, edges = 0, vertices = 0;
    for (int k = 0; k < 4000; ++k) {
      const Vector3d x = box.min() + Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.sizes());
      const auto d = s.signed_distance(x);
      EXPECT_NEAR(d.normal.norm(), 1.0, 1e-12);
      if (d.distance > 0) {
        ++outside;
        edges += d.feature == SurfaceFeature::kEdge;
        vertices += d.feature == SurfaceFeature::kVertex;
        EXPECT_NEAR((x - d.point).norm(), d.distance, kGeomTol);
        EXPECT_LE(s.max_plane_distance(d.point).value, kGeomTol);          // p in P
        EXPECT_GE(d.distance, s.max_plane_distance(x).value - kGeomTol);  // plane value is a lower bound
        for (const Vector3d& y : s.vertices()) EXPECT_LE((x - d.point).dot(y - d.point), kGeomTol);
      } else {
        double depth = 1e300;
        for (const auto& f : s.faces()) depth = std::min(depth, f.offset - f.normal.dot(x));
        EXPECT_NEAR(d.distance, -depth, kGeomTol);
        EXPECT_NEAR(s.faces()[d.face].offset - s.faces()[d.face].normal.dot(x), depth, kGeomTol);
      }
    }
    // The sample must exercise all three outside branches.
    EXPECT_GT(outside, 500);
    EXPECT_GT(edges, 100);
    EXPECT_GT(vertices, 20);
  }
}

TEST(ConvexQuery, BoundingRadiusAboutTheCentreOfMass) {
  const ConvexShape p = ConvexShape::prism(0.5, 6, 2.0);
  const Vector3d com = p.mass_properties(1.0).com;
  EXPECT_NEAR(p.bounding_radius(com), std::sqrt(0.25 + 1.0), kGeomTol);
  for (const Vector3d& v : p.vertices()) EXPECT_TRUE(p.bounding_box().contains(v));
}

// ---------------------------------------------------------------------------
TEST(ShapeErrors, InvalidInputIsRejectedWithAMessage) {
  auto has = [](const std::string& msg, const std::string& part) {
    EXPECT_NE(msg.find(part), std::string::npos) << "message: " << msg << "\nexpected: " << part;
  };
  has(error_of([] { ConvexShape::hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}); }),
      "convex: needs at least 4 points that are not coplanar, got 3");
  std::vector<Vector3d> dup = cube_corners(0.5);
  dup.push_back(dup[5] + Vector3d(1e-12, 0, 0));
  has(error_of([&] { ConvexShape::hull(dup, "body 'crate': convex"); }),
      "body 'crate': convex: duplicate points: vertices[5] (0.5, -0.5, 1) and vertices[8]");
  has(error_of([] { ConvexShape::hull({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {-1, -1, -1}}); }),
      "all 5 points are collinear");
  has(error_of([] { ConvexShape::hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.3, 0.2, 1e-12}}); }),
      "all 5 points are coplanar");
  has(error_of([] { ConvexShape::hull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, NAN}}); }),
      "vertices[3] is not finite");
  has(error_of([] { ConvexShape::box(Vector3d(0.3, -0.1, 0.2)); }),
      "box: half_extents must be positive and finite, got [0.3, -0.1, 0.2]");
  has(error_of([] { ConvexShape::prism(0.5, 2, 1.0); }), "prism: sides must be at least 3, got 2");
  has(error_of([] { ConvexShape::prism(0.0, 8, 1.0); }), "prism: radius must be positive and finite, got 0");
  has(error_of([] { ConvexShape::prism(0.5, 8, -1.0); }), "prism: height must be positive and finite, got -1");
  has(error_of([] { ConvexShape::box(Vector3d(1, 1, 1)).mass_properties(0.0); }), "density must be positive");
  Matrix3d shear = Matrix3d::Identity();
  shear(0, 1) = 0.1;
  has(error_of([&] { ConvexShape::box(Vector3d(1, 1, 1)).transformed(shear, Vector3d::Zero()); }),
      "must be a proper rotation");
  has(error_of([] { ConvexShape::box(Vector3d(1, 1, 1)).transformed(-Matrix3d::Identity(), Vector3d::Zero()); }),
      "must be a proper rotation");
  // A non-convex surface handed to the loop constructor.
  const ConvexShape cube = ConvexShape::box(Vector3d(1, 1, 1));
  std::vector<Vector3d> v = cube.vertices();
  std::vector<std::vector<int>> loops;
  for (const auto& f : cube.faces()) loops.push_back(f.loop);
  v[6] = Vector3d(0.5, 0.5, 1.5);  // dent the top corner inward: faces no longer planar
  has(error_of([&] { ConvexShape::from_loops(v, loops, "dented"); }), "dented: ");
}

// ---------------------------------------------------------------------------
// Not a pass/fail test (disabled; run with --gtest_also_run_disabled_tests):
// prints the cost of the per-node queries for docs/shapes.md (Release build).
TEST(ShapeBench, DISABLED_QueryCost) {
  struct Item {
    std::string name;
    ConvexShape shape;
  };
  const std::vector<Item> items = {{"box", ConvexShape::box(Vector3d(0.5, 0.5, 1.5))},
                                   {"prism 24", ConvexShape::prism(0.5, 24, 1.0)}};
  for (const Item& it : items) {
    const Eigen::AlignedBox3d box = it.shape.bounding_box();
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-0.05, 1.05);
    std::vector<Vector3d> x(4096);
    for (Vector3d& p : x) p = box.min() + Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.sizes());
    const int reps = 100;
    double sink = 0;
    auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r)
      for (const Vector3d& p : x) sink += it.shape.max_plane_distance(p).value;
    auto t1 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r)
      for (const Vector3d& p : x) sink += it.shape.signed_distance(p).distance;
    auto t2 = std::chrono::steady_clock::now();
    const double n = static_cast<double>(reps) * x.size();
    std::printf("[measured] %-9s max_plane_distance %5.1f ns/query, signed_distance %5.1f ns/query (%.3g)\n",
                it.name.c_str(), std::chrono::duration<double, std::nano>(t1 - t0).count() / n,
                std::chrono::duration<double, std::nano>(t2 - t1).count() / n, sink);
    EXPECT_TRUE(std::isfinite(sink));
  }
  // Set-up costs: the hull of 1000 random points.
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vector3d> cloud(1000);
  for (Vector3d& p : cloud) p = Vector3d(g(rng), g(rng), g(rng));
  const auto t0 = std::chrono::steady_clock::now();
  const ConvexShape hull = ConvexShape::hull(cloud);
  const auto t1 = std::chrono::steady_clock::now();
  std::printf("[measured] hull of 1000 gaussian points: %zu faces, %.2f ms\n", hull.faces().size(),
              std::chrono::duration<double, std::milli>(t1 - t0).count());
}
