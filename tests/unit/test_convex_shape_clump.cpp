// Clumps of convex pieces: mass properties against hand-made parallel-axis
// closed forms, glued faces, the union distance, and rejected overlaps.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <string>
#include <vector>

#include "freestand/contact_nodes.h"
#include "freestand/convex_shape.h"
#include "freestand/input_error.h"
#include "freestand/shape_clump.h"

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using freestand::Clump;
using freestand::ClumpPiece;
using freestand::ConvexShape;
using freestand::FaceCover;
using freestand::MassProperties;

namespace {

// See test_convex_shape.cpp: round-off is ~1e-15 relative; 1e-12 catches any
// wrong term.
constexpr double kMassTol = 1e-12;

ClumpPiece box_piece(const Vector3d& half, const Vector3d& offset,
                     const Quaterniond& q = Quaterniond::Identity()) {
  ClumpPiece p{ConvexShape::box(half)};
  p.offset = offset;
  p.orientation = q;
  return p;
}

// Closed form of a box of half extents h about its own centre, principal axes.
Matrix3d box_inertia(const Vector3d& h, double mass) {
  return Vector3d(mass * (h.y() * h.y() + h.z() * h.z()) / 3, mass * (h.x() * h.x() + h.z() * h.z()) / 3,
                  mass * (h.x() * h.x() + h.y() * h.y()) / 3)
      .asDiagonal();
}

void expect_mass_near(const MassProperties& got, const MassProperties& want, const std::string& what) {
  const double err = std::max({std::abs(got.volume - want.volume) / want.volume,
                               (got.com - want.com).norm() / std::cbrt(want.volume),
                               (got.inertia - want.inertia).cwiseAbs().maxCoeff() / want.inertia.cwiseAbs().maxCoeff()});
  std::printf("[measured] mass properties, %s: largest relative error %.1e\n", what.c_str(), err);
  EXPECT_NEAR(got.volume, want.volume, kMassTol * want.volume) << what;
  EXPECT_NEAR(got.mass, want.mass, kMassTol * want.mass) << what;
  EXPECT_LE((got.com - want.com).norm(), kMassTol * std::cbrt(want.volume)) << what << " " << got.com.transpose();
  EXPECT_LE((got.inertia - want.inertia).cwiseAbs().maxCoeff(), kMassTol * want.inertia.cwiseAbs().maxCoeff())
      << what << "\n"
      << got.inertia << "\nvs\n"
      << want.inertia;
}

// The L-shaped cabinet: a low wide box with a tall narrow box on its +x end.
Clump l_cabinet() {
  return Clump({box_piece({0.5, 0.3, 0.2}, {0, 0, 0}), box_piece({0.15, 0.3, 0.6}, {0.35, 0, 0.4})});
}

}  // namespace

TEST(ShapeClump, TwoHalvesMakeTheWholeBox) {
  const Clump c({box_piece({0.25, 0.3, 0.5}, {-0.25, 0, 0}), box_piece({0.25, 0.3, 0.5}, {0.25, 0, 0})});
  expect_mass_near(c.mass_properties(2000), ConvexShape::box(Vector3d(0.5, 0.3, 0.5)).mass_properties(2000),
                   "halves");
  // The glued faces (+x of piece 0, -x of piece 1) are inside the body.
  EXPECT_EQ(c.cover({0, 3}), FaceCover::kCovered);
  EXPECT_EQ(c.cover({1, 5}), FaceCover::kCovered);
  for (int f : {0, 1, 2, 4, 5}) EXPECT_EQ(c.cover({0, f}), FaceCover::kExposed) << f;
  EXPECT_TRUE(c.notes().empty());
  // Nodes cover exactly the outer surface, 2 (1 x 0.6 + 1 x 1 + 0.6 x 1) = 4.4 m^2.
  freestand::NodeOptions o;
  o.spacing = 0.1;
  double area = 0;
  for (const auto& n : freestand::make_contact_nodes(c, o)) {
    area += n.area;
    EXPECT_FALSE((n.piece == 0 && n.face == 3) || (n.piece == 1 && n.face == 5));
  }
  EXPECT_NEAR(area, 4.4, 1e-13);
  // Two bases on the lowest plane.
  EXPECT_EQ(c.base_faces().size(), 2u);
  EXPECT_NEAR(c.bounding_radius(Vector3d(0, 0, 0.5)), std::sqrt(0.25 + 0.09 + 0.25), 1e-15);
}

TEST(ShapeClump, LShapedCabinetClosedForm) {
  const double rho = 700;
  const Vector3d ha(0.5, 0.3, 0.2), hb(0.15, 0.3, 0.6);
  const double ma = rho * 8 * ha.prod(), mb = rho * 8 * hb.prod();
  const Vector3d ca(0, 0, 0.2), cb(0.35, 0, 1.0);
  MassProperties want;
  want.volume = 8 * ha.prod() + 8 * hb.prod();
  want.mass = ma + mb;
  want.com = (ma * ca + mb * cb) / (ma + mb);
  // Parallel axes written out: I = I_c + m (|d|^2 1 - d d^T).
  for (const auto& [m, c, h] : {std::tuple{ma, ca, ha}, std::tuple{mb, cb, hb}}) {
    const Vector3d d = c - want.com;
    want.inertia += box_inertia(h, m);
    want.inertia(0, 0) += m * (d.y() * d.y() + d.z() * d.z());
    want.inertia(1, 1) += m * (d.x() * d.x() + d.z() * d.z());
    want.inertia(2, 2) += m * (d.x() * d.x() + d.y() * d.y());
    want.inertia(0, 1) -= m * d.x() * d.y();
    want.inertia(0, 2) -= m * d.x() * d.z();
    want.inertia(1, 2) -= m * d.y() * d.z();
  }
  want.inertia(1, 0) = want.inertia(0, 1);
  want.inertia(2, 0) = want.inertia(0, 2);
  want.inertia(2, 1) = want.inertia(1, 2);
  const Clump c = l_cabinet();
  expect_mass_near(c.mass_properties(rho), want, "L cabinet");
  EXPECT_LT(want.inertia(0, 2), -1.0);  // the test has a real product of inertia to get wrong
  // The tall box's base is glued on; the low box's top is 30 % covered.
  EXPECT_EQ(c.cover({1, 0}), FaceCover::kCovered);
  EXPECT_EQ(c.cover({0, 1}), FaceCover::kPartlyCovered);
  EXPECT_NEAR(c.covered_fraction({0, 1}), 0.3, 1e-12);
  ASSERT_EQ(c.notes().size(), 1u);
  EXPECT_NE(c.notes()[0].find("piece 0 face 1: 30.0% of its area"), std::string::npos) << c.notes()[0];
}

TEST(ShapeClump, EccentricRotatedStatueOnPlinthWithTwoDensities) {
  // Stone plinth 0.8 x 0.8 x 1.0; bronze statue 0.3 x 0.2 x 1.2 turned 30
  // degrees about z, standing off-centre on it.
  const double stone = 2600, bronze = 8000;
  const Vector3d hp(0.4, 0.4, 0.5), hs(0.15, 0.1, 0.6);
  const Quaterniond q(AngleAxisd(30.0 * 3.14159265358979323846 / 180.0, Vector3d::UnitZ()));
  const Vector3d off(0.1, -0.15, 1.0);
  const Clump c({box_piece(hp, Vector3d::Zero()), box_piece(hs, off, q)});

  const double mp = stone * 8 * hp.prod(), ms = bronze * 8 * hs.prod();
  const Vector3d cp(0, 0, 0.5), cs = off + Vector3d(0, 0, 0.6);
  MassProperties want;
  want.volume = 8 * hp.prod() + 8 * hs.prod();
  want.mass = mp + ms;
  want.com = (mp * cp + ms * cs) / want.mass;
  const Matrix3d R = q.toRotationMatrix();
  want.inertia = box_inertia(hp, mp) + R * box_inertia(hs, ms) * R.transpose();
  for (const auto& [m, cc] : {std::pair{mp, cp}, std::pair{ms, cs}}) {
    const Vector3d d = cc - want.com;
    want.inertia += m * (d.squaredNorm() * Matrix3d::Identity() - d * d.transpose());
  }
  expect_mass_near(c.mass_properties({stone, bronze}), want, "statue on plinth");
  EXPECT_GT(std::abs(want.inertia(0, 1)), 1.0);
  EXPECT_EQ(c.cover({1, 0}), FaceCover::kCovered);
  EXPECT_NEAR(c.covered_fraction({0, 1}), 0.3 * 0.2 / 0.64, 1e-12);
  EXPECT_THROW(c.mass_properties(std::vector<double>{stone}), freestand::InputError);
}

TEST(ShapeClump, UnionDistanceIgnoresGluedFaces) {
  const Clump c = l_cabinet();  // low box x -0.5..0.5, z 0..0.4; tall box x 0.2..0.5, z 0.4..1.6
  // Inside the tall box just above its glued base: the way out is its -x
  // face (0.1 away), not the glued base 0.01 below.
  auto d = c.signed_distance(Vector3d(0.3, 0.0, 0.41));
  EXPECT_EQ(d.piece, 1);
  EXPECT_NEAR(d.surface.distance, -0.1, 1e-12);
  EXPECT_EQ(d.surface.face, 5);
  EXPECT_LE((d.surface.normal + Vector3d::UnitX()).norm(), 1e-15);
  // Inside the low box: its own least-penetration face.
  d = c.signed_distance(Vector3d(-0.3, 0.0, 0.05));
  EXPECT_EQ(d.piece, 0);
  EXPECT_NEAR(d.surface.distance, -0.05, 1e-12);
  EXPECT_EQ(d.surface.face, 0);
  // Outside, nearest to the low box's top -x edge: sqrt(0.1^2 + 0.1^2).
  d = c.signed_distance(Vector3d(-0.6, 0.0, 0.5));
  EXPECT_EQ(d.piece, 0);
  EXPECT_NEAR(d.surface.distance, std::sqrt(0.02), 1e-12);
  EXPECT_EQ(d.surface.feature, freestand::SurfaceFeature::kEdge);
  // In the inner corner of the L, outside: 0.05 from both the low top and the tall -x face.
  d = c.signed_distance(Vector3d(0.15, 0.0, 0.45));
  EXPECT_NEAR(d.surface.distance, 0.05, 1e-12);
  // A NaN point gives NaN.
  EXPECT_TRUE(std::isnan(c.signed_distance(Vector3d(0.3, NAN, 0.41)).surface.distance));
}

TEST(ShapeClump, OverlappingPiecesAreRejected) {
  try {
    Clump({box_piece({0.5, 0.5, 0.5}, {0, 0, 0}), box_piece({0.2, 0.2, 0.2}, {0.0, 0.0, 0.99})}, "body 'vase'");
    FAIL() << "no InputError";
  } catch (const freestand::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("body 'vase': pieces 0 and 1 overlap (by 0.01 m along (0, 0, "),
              std::string::npos)
        << e.what();
  }
  // A tilted piece poking into the other by a corner only.
  ClumpPiece tilted = box_piece({0.2, 0.2, 0.2}, {0.45, 0.45, 1.0},
                                Quaterniond(AngleAxisd(0.7, Vector3d(1, -1, 0).normalized())));
  EXPECT_THROW(Clump({box_piece({0.5, 0.5, 0.5}, {0, 0, 0}), tilted}), freestand::InputError);
  ClumpPiece bad = box_piece({0.2, 0.2, 0.2}, {3, 0, 0});
  bad.orientation.coeffs() *= 2.0;
  EXPECT_THROW(Clump({box_piece({0.5, 0.5, 0.5}, {0, 0, 0}), bad}), freestand::InputError);
}
