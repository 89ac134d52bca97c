// Body-on-body node contact (body_contact.h): nodes of each body against the
// faces of the other, both ways. Geometry checks on boxes and drums 0.4 to
// 1.2 m in size with overlaps of 1e-5 m: positions are O(1) m, so a computed
// depth carries a round-off of a few 1e-16 m. Tolerances of 1e-14 m on depths
// (1e-9 of the overlap) and 1e-13 on rotated quantities are round-off, while
// every wrong choice (a wrong face, a missing transform term, a sign) moves
// them by the overlap (1e-5 m) or by O(1).

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "freestand/body_contact.h"
#include "freestand/contact_law.h"
#include "freestand/contact_nodes.h"
#include "freestand/convex_shape.h"
#include "freestand/input_error.h"
#include "freestand/shape_clump.h"

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using freestand::BodyContactModel;
using freestand::BodyContactOptions;
using freestand::BodyMotion;
using freestand::Clump;
using freestand::ClumpPiece;
using freestand::ContactLaw;
using freestand::ContactParams;
using freestand::ContactSide;
using freestand::ConvexShape;
using freestand::FaceRef;
using freestand::NodeContact;
using freestand::NodeOptions;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDelta = 1e-5;     // imposed interpenetration (m)
constexpr double kDepthTol = 1e-14; // m, round-off on O(1) m coordinates

struct Body {
  Clump geometry;
  Vector3d com;
  BodyContactModel model;
};

Body make_body(const Clump& geometry, const NodeOptions& options,
               const Vector3d* com_override = nullptr) {
  const Vector3d com = com_override ? *com_override : geometry.mass_properties(1000.0).com;
  const auto nodes =
      options.spacing < 0 ? std::vector<freestand::ContactNode>{}
                          : freestand::make_contact_nodes(geometry, options);
  return Body{geometry, com, BodyContactModel(geometry, com, nodes)};
}

NodeOptions spacing(double h) {
  NodeOptions o;
  o.spacing = h;
  return o;
}

// Motion of a body whose body-frame origin is at `origin` with rotation q.
BodyMotion placed(const Body& b, const Vector3d& origin, const Quaterniond& q = Quaterniond::Identity()) {
  BodyMotion m;
  m.orientation = q;
  m.position = origin + q * b.com;
  return m;
}

// The same motion seen after a rigid motion x -> Q x + T of the world.
BodyMotion moved(const BodyMotion& m, const Quaterniond& Q, const Vector3d& T) {
  BodyMotion r;
  r.position = Q * m.position + T;
  r.orientation = (Q * m.orientation).normalized();
  r.velocity = Q * m.velocity;
  r.angular_velocity = Q * m.angular_velocity;
  return r;
}

std::vector<NodeContact> contacts(const Body& a, const BodyMotion& ma, const Body& b,
                                  const BodyMotion& mb, BodyContactOptions o = {}) {
  std::vector<NodeContact> out;
  freestand::find_body_contacts(a.model, ma, b.model, mb, o, out);
  return out;
}

std::vector<NodeContact> of_side(const std::vector<NodeContact>& all, ContactSide s) {
  std::vector<NodeContact> out;
  for (const auto& c : all)
    if (c.side == s) out.push_back(c);
  return out;
}

Quaterniond random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
}

// Box A (0.6 x 0.4 x 0.8) resting on box B (1.0 x 0.8 x 0.6), its footprint
// x in [-0.25, 0.35], y in [-0.25, 0.15]: between B's 0.1 m grid lines.
struct Stack {
  Body a = make_body(Clump(ConvexShape::box({0.3, 0.2, 0.4})), spacing(0.1));
  Body b = make_body(Clump(ConvexShape::box({0.5, 0.4, 0.3})), spacing(0.1));
  BodyMotion ma = placed(a, {0.05, -0.05, 0.6 - kDelta});
  BodyMotion mb = placed(b, {0.0, 0.0, 0.0});
};

}  // namespace

TEST(BodyContact, RestingBoxFaceOnEveryBaseNodeFoundNormalUpOverlapImposed) {
  Stack s;
  const auto all = contacts(s.a, s.ma, s.b, s.mb);
  const auto a_on_b = of_side(all, ContactSide::kNodeOfA);
  // Side 0: exactly the nodes of A's base face (face 0), each once.
  std::set<int> expected, found;
  for (std::size_t i = 0; i < s.a.model.nodes().size(); ++i)
    if (s.a.model.nodes()[i].face == 0) expected.insert(static_cast<int>(i));
  for (const auto& c : a_on_b) {
    EXPECT_TRUE(found.insert(c.node).second) << "node " << c.node << " twice";
    EXPECT_EQ(c.normal, Vector3d(0, 0, 1));  // exactly +z
    EXPECT_EQ(c.face, 1);                    // B's top
    EXPECT_NEAR(c.overlap, kDelta, kDepthTol);
    EXPECT_NEAR(c.facing, 1.0, 1e-15);
    const auto& node = s.a.model.nodes()[c.node];
    EXPECT_NEAR(c.area, 0.5 * node.area, 1e-15 * node.area);
    EXPECT_NEAR(c.node_face_area, 0.24, 1e-15);
    const Vector3d world = Vector3d(0.05, -0.05, 0.6 - kDelta) + node.position;
    EXPECT_LT((c.point - world).norm(), 1e-15);
    EXPECT_LT((c.lever_a - (world - s.ma.position)).norm(), 1e-15);
    EXPECT_LT((c.lever_b - (world - s.mb.position)).norm(), 1e-15);
    EXPECT_EQ(c.velocity, Vector3d::Zero());
    EXPECT_EQ(c.key, 2u * c.node);
  }
  EXPECT_EQ(found, expected);
  EXPECT_EQ(expected.size(), 35u);  // 7 x 5 grid at 0.1 m
  // Side 1: B's top nodes under A's footprint, normal exactly -z (A's base).
  std::set<int> expected_b, found_b;
  for (std::size_t i = 0; i < s.b.model.nodes().size(); ++i) {
    const auto& n = s.b.model.nodes()[i];
    if (n.face == 1 && n.position.x() > -0.25 && n.position.x() < 0.35 && n.position.y() > -0.25 &&
        n.position.y() < 0.15)
      expected_b.insert(static_cast<int>(i));
  }
  for (const auto& c : of_side(all, ContactSide::kNodeOfB)) {
    found_b.insert(c.node);
    EXPECT_EQ(c.normal, Vector3d(0, 0, -1));
    EXPECT_EQ(c.face, 0);
    EXPECT_NEAR(c.overlap, kDelta, kDepthTol);
    EXPECT_EQ(c.key, 2u * c.node + 1u);
  }
  EXPECT_EQ(found_b, expected_b);
  EXPECT_EQ(expected_b.size(), 24u);
}

TEST(BodyContact, RotatingTheWholeStackRotatesEveryContact) {
  Stack s;
  const auto ref = contacts(s.a, s.ma, s.b, s.mb);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Quaterniond Q = random_rotation(rng);
    const Vector3d T(3.0 * trial, -1.0, 0.5 * trial);
    const auto got = contacts(s.a, moved(s.ma, Q, T), s.b, moved(s.mb, Q, T));
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].key, ref[k].key);
      EXPECT_EQ(got[k].face, ref[k].face);
      EXPECT_NEAR(got[k].overlap, ref[k].overlap, 1e-13);
      EXPECT_LT((got[k].normal - Q * ref[k].normal).norm(), 1e-13);
      EXPECT_LT((got[k].point - (Q * ref[k].point + T)).norm(), 1e-13);
      EXPECT_LT((got[k].lever_a - Q * ref[k].lever_a).norm(), 1e-13);
      EXPECT_LT((got[k].lever_b - Q * ref[k].lever_b).norm(), 1e-13);
      EXPECT_NEAR(got[k].area, ref[k].area, 1e-15);
    }
  }
}

// Column drums: two equal 20-sided drums stacked flush. The rim nodes of each
// base lie exactly on the other drum's side planes (depth 0 there, kDelta
// below the top): they must stay in contact with the +z normal whatever the
// round-off, over many slightly different poses.
TEST(BodyContact, FlushDrumsRimNodesNeverFlipOrDropOut) {
  const Clump drum(ConvexShape::prism(0.5, 20, 0.6));
  Body a = make_body(drum, spacing(0.1));
  Body b = make_body(drum, spacing(0.1));
  std::size_t base_nodes = 0;
  for (const auto& n : a.model.nodes()) base_nodes += n.face == 0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::size_t worst_missing = 0;
  double worst_normal = 0.0, worst_depth = 0.0;
  for (int step = 0; step < 200; ++step) {
    const Quaterniond Q = step == 0 ? Quaterniond::Identity() : random_rotation(rng);
    // Pose noise of 1e-13 rad and 1e-13 m, far above the round-off.
    const Quaterniond wobble(AngleAxisd(1e-13, Vector3d(u(rng), u(rng), u(rng)).normalized()));
    const Vector3d shift(1e-13 * u(rng), 1e-13 * u(rng), 0.0);
    const BodyMotion ma = moved(placed(a, Vector3d(0, 0, 0.6 - kDelta) + shift, wobble), Q, Vector3d::Zero());
    const BodyMotion mb = moved(placed(b, Vector3d::Zero()), Q, Vector3d::Zero());
    const auto all = contacts(a, ma, b, mb);
    const auto a_on_b = of_side(all, ContactSide::kNodeOfA);
    const auto b_on_a = of_side(all, ContactSide::kNodeOfB);
    worst_missing = std::max(worst_missing, 2 * base_nodes - a_on_b.size() - b_on_a.size());
    for (const auto& c : all) {
      EXPECT_TRUE((c.side == ContactSide::kNodeOfA && c.face == 1) ||
                  (c.side == ContactSide::kNodeOfB && c.face == 0));
      const Vector3d up = Q * Vector3d::UnitZ();
      worst_normal = std::max(worst_normal, (c.normal - (c.side == ContactSide::kNodeOfA ? up : Vector3d(-up))).norm());
      worst_depth = std::max(worst_depth, std::abs(c.overlap - kDelta));
    }
    ASSERT_EQ(a_on_b.size(), base_nodes) << "step " << step;
    ASSERT_EQ(b_on_a.size(), base_nodes) << "step " << step;
  }
  EXPECT_LT(worst_normal, 1e-12);  // wobble 1e-13 rad + round-off
  EXPECT_LT(worst_depth, 1e-12);   // wobble 1e-13 rad x 0.5 m
  std::printf("[measured] flush drums, 200 poses: %zu of %zu base nodes per side always found, "
              "normal error %.1e, depth error %.1e m\n",
              base_nodes - worst_missing / 2, base_nodes, worst_normal, worst_depth);
  // The band is what keeps them: narrower than the overlap, the rim nodes
  // (least depth on a side face, facing 0) drop out.
  BodyContactOptions narrow;
  narrow.band = 0.1 * kDelta;
  const auto lost = contacts(a, placed(a, {0, 0, 0.6 - kDelta}), b, placed(b, Vector3d::Zero()), narrow);
  EXPECT_LT(lost.size(), 2 * base_nodes);
}

TEST(BodyContact, TiltedBoxOnEdgeFindsOnlyTheEdgeNodes) {
  const double theta = 0.1, a_half = 0.3;
  Body a = make_body(Clump(ConvexShape::box({a_half, 0.2, 0.4})), spacing(0.1));
  Body b = make_body(Clump(ConvexShape::box({0.5, 0.4, 0.3})), spacing(0.1));
  const Quaterniond q(AngleAxisd(theta, Vector3d::UnitY()));  // edge x = +a goes down
  // Edge x = +a, z = 0 at world x = 0.05 (between B's grid lines), z = 0.6 - delta.
  const Vector3d origin(0.05 - a_half * std::cos(theta), 0.0, 0.6 - kDelta + a_half * std::sin(theta));
  const auto all = contacts(a, placed(a, origin, q), b, placed(b, Vector3d::Zero()));
  EXPECT_TRUE(of_side(all, ContactSide::kNodeOfB).empty());  // the wedge is 1e-4 m wide
  std::set<int> expected, found;
  for (std::size_t i = 0; i < a.model.nodes().size(); ++i) {
    const auto& n = a.model.nodes()[i];
    // On the edge, from the base (facing cos theta) or the +x side (sin theta);
    // the +-y faces' corner nodes face sideways (facing 0) and drop out.
    if (std::abs(n.position.x() - a_half) < 1e-12 && std::abs(n.position.z()) < 1e-12 &&
        (n.face == 0 || n.face == 3))
      expected.insert(static_cast<int>(i));
  }
  for (const auto& c : all) {
    found.insert(c.node);
    const auto& n = a.model.nodes()[c.node];
    EXPECT_EQ(c.normal, Vector3d(0, 0, 1));
    EXPECT_NEAR(c.overlap, kDelta, kDepthTol);
    EXPECT_NEAR(c.facing, n.face == 0 ? std::cos(theta) : std::sin(theta), 1e-15);
    EXPECT_NEAR(c.area, 0.5 * c.facing * n.area, 1e-15);
  }
  EXPECT_EQ(found, expected);
  EXPECT_EQ(expected.size(), 10u);  // 5 nodes along the 0.4 m edge, from 2 faces
}

TEST(BodyContact, SeparatedBodiesGiveNoContacts) {
  Stack s;
  std::vector<NodeContact> out;
  const double gaps[] = {1e-9, 1e-6, 1e-3, 10.0};
  for (double gap : gaps) {
    // Above, and beside (side faces 1e-9 .. 10 m apart).
    freestand::find_body_contacts(s.a.model, placed(s.a, {0.05, -0.05, 0.6 + gap}), s.b.model, s.mb, {}, out);
    EXPECT_TRUE(out.empty()) << gap;
    freestand::find_body_contacts(s.a.model, placed(s.a, {0.8 + gap, 0.0, 0.3}), s.b.model, s.mb, {}, out);
    EXPECT_TRUE(out.empty()) << gap;
  }
  // Touching (gap 0): whatever round-off reports is a round-off overlap.
  freestand::find_body_contacts(s.a.model, placed(s.a, {0.05, -0.05, 0.6}), s.b.model, s.mb, {}, out);
  for (const auto& c : out) EXPECT_LT(c.overlap, 1e-15);
}

// Relative velocity = rate of the node's position in the face body's frame,
// rotated to world: R_F d/dt[R_F^T (p(t) - x_F(t))]. Central differences over
// the exact rigid motions, h = 1e-5 s: truncation ~ h^2 omega^3 r / 6 < 1e-9,
// round-off ~ 1e-16 / h = 1e-11; a wrong sign or a missing omega x r term
// is off by O(1) m/s.
TEST(BodyContact, RelativeVelocityMatchesFiniteDifferences) {
  Body a = make_body(Clump(ConvexShape::box({0.3, 0.2, 0.4})), spacing(0.1));
  Body b = make_body(Clump(ConvexShape::prism(0.5, 7, 0.6)), spacing(0.1));
  const Quaterniond qa(AngleAxisd(0.2, Vector3d(1, 2, 0).normalized()));
  BodyMotion ma = placed(a, {0.1, 0.05, 0.64}, qa);
  BodyMotion mb = placed(b, {0.0, 0.0, 0.0}, Quaterniond(AngleAxisd(0.3, Vector3d::UnitZ())));
  ma.velocity = {0.7, -0.4, -0.9};
  ma.angular_velocity = {1.3, -2.1, 0.8};
  mb.velocity = {-0.2, 0.5, 0.3};
  mb.angular_velocity = {-0.6, 0.9, 2.5};
  const auto all = contacts(a, ma, b, mb);
  ASSERT_FALSE(of_side(all, ContactSide::kNodeOfA).empty());
  ASSERT_FALSE(of_side(all, ContactSide::kNodeOfB).empty());
  auto at = [](const BodyMotion& m, double t) {
    BodyMotion r = m;
    r.position = m.position + t * m.velocity;
    const double w = m.angular_velocity.norm();
    r.orientation = Quaterniond(AngleAxisd(w * t, m.angular_velocity / w)) * m.orientation;
    return r;
  };
  const double h = 1e-5;
  double worst = 0.0, worst_rate = 0.0;
  std::map<std::uint64_t, double> plus, minus;
  for (const auto& c : contacts(a, at(ma, h), b, at(mb, h))) plus[c.key] = c.overlap;
  for (const auto& c : contacts(a, at(ma, -h), b, at(mb, -h))) minus[c.key] = c.overlap;
  int rates = 0;
  for (const auto& c : all) {
    const bool of_a = c.side == ContactSide::kNodeOfA;
    const Body& nb = of_a ? a : b;
    const BodyMotion& mn = of_a ? ma : mb;
    const BodyMotion& mf = of_a ? mb : ma;
    const Vector3d y = nb.model.nodes()[c.node].position - nb.com;
    auto local = [&](double t) {
      const BodyMotion n = at(mn, t), f = at(mf, t);
      return Vector3d(f.orientation.inverse() * (n.position + n.orientation * y - f.position));
    };
    const Vector3d fd = mf.orientation * Vector3d((local(h) - local(-h)) / (2 * h));
    worst = std::max(worst, (fd - c.velocity).norm());
    EXPECT_LT((fd - c.velocity).norm(), 1e-8) << "node " << c.node;
    if (plus.count(c.key) && minus.count(c.key)) {  // same face both sides: d(overlap)/dt = -n.v
      const double rate = (plus[c.key] - minus[c.key]) / (2 * h);
      worst_rate = std::max(worst_rate, std::abs(rate + c.normal.dot(c.velocity)));
      EXPECT_NEAR(rate, -c.normal.dot(c.velocity), 1e-8);
      ++rates;
    }
  }
  EXPECT_GT(rates, 0);
  std::printf("[measured] relative velocity vs finite differences (%zu contacts): %.1e m/s; "
              "overlap rate vs -n.v (%d): %.1e m/s\n", all.size(), worst, rates, worst_rate);
}

namespace {
struct Loads {
  Vector3d fa = Vector3d::Zero(), ta = Vector3d::Zero(), fb = Vector3d::Zero(), tb = Vector3d::Zero();
};
Loads loads(const std::vector<NodeContact>& all, const ContactLaw& law, double m_red) {
  Loads l;
  for (const auto& c : all) {
    freestand::ContactHistory hist;
    const auto f = law.compute(freestand::to_contact_point(c, m_red), 1e-6, hist);
    freestand::apply_node_force(c, f.force, l.fa, l.ta, l.fb, l.tb);
  }
  return l;
}
ContactLaw linear_law(double k_a) {
  ContactParams p;
  p.stiffness_per_area = k_a;
  p.damping_ratio = 0.2;
  p.mu_s = p.mu_k = 0.6;
  return ContactLaw(p);
}
}  // namespace

// Uniform overlap, linear law p = k_a delta: the resultant is k_a delta A
// and its line of action passes through the centroid of the pressed area.
// Node areas and first moments are exact to 1e-14 relative; each depth
// carries ~1e-16 m of round-off on delta = 1e-5 m, i.e. 1e-11 relative, so
// forces and moments are checked to 1e-9 relative. A missing node, a wrong
// weight or a wrong lever arm is off by 1e-3 or more.
TEST(BodyContact, UniformPressureGivesExactResultantAndMoment) {
  const double k_a = 2e9;
  const ContactLaw law = linear_law(k_a);
  const double q = k_a * kDelta;  // 2e4 Pa
  const double kRel = 1e-9;
  // (1) Equal boxes stacked flush, both passes (weight 1/2 each) and rotated
  // as a whole: k_a per unit area over the whole face, as on the table.
  {
    const Clump box(ConvexShape::box({0.3, 0.2, 0.4}));
    Body a = make_body(box, spacing(0.1)), b = make_body(box, spacing(0.1));
    const Quaterniond Q(AngleAxisd(0.7, Vector3d(1, -2, 3).normalized()));
    const Vector3d T(1, 2, 3);
    const BodyMotion ma = moved(placed(a, {0, 0, 0.8 - kDelta}), Q, T);
    const BodyMotion mb = moved(placed(b, Vector3d::Zero()), Q, T);
    const Loads l = loads(contacts(a, ma, b, mb), law, 100.0);
    const Vector3d expected = q * 0.24 * (Q * Vector3d::UnitZ());
    EXPECT_LT((l.fa - expected).norm(), kRel * expected.norm());
    EXPECT_LT((l.fa + l.fb).norm(), kRel * expected.norm());
    // Both centroids are on the COM axis: no torque on either body.
    EXPECT_LT(l.ta.norm(), kRel * expected.norm());
    EXPECT_LT(l.tb.norm(), kRel * expected.norm());
    std::printf("[measured] flush stack: resultant %.12e N (k_a delta A = %.12e), torque %.1e N m\n",
                l.fa.norm(), expected.norm(), l.ta.norm());
  }
  // (2) A small eccentric statue (COM off the base centroid) off-centre on a
  // large pedestal; only the statue's base nodes (pedestal nodes on its base
  // face, which cannot reach): pass weight 1 gives k_a delta A_base.
  {
    const Vector3d com_a(0.08, -0.05, 0.3);  // eccentric (e.g. a two-density clump)
    Body a = make_body(Clump(ConvexShape::box({0.2, 0.15, 0.4})), spacing(0.05), &com_a);
    NodeOptions base_only = spacing(0.1);
    base_only.faces = {FaceRef{0, 0}};
    Body b = make_body(Clump(ConvexShape::box({0.5, 0.4, 0.3})), base_only);
    const Vector3d origin(0.17, -0.12, 0.6 - kDelta);
    const Quaterniond yaw(AngleAxisd(0.4, Vector3d::UnitZ()));
    const BodyMotion ma = placed(a, origin, yaw), mb = placed(b, Vector3d::Zero());
    BodyContactOptions full;
    full.pass_weight = 1.0;
    const Loads l = loads(contacts(a, ma, b, mb, full), law, 100.0);
    const double area = 0.4 * 0.3;
    const Vector3d F = q * area * Vector3d::UnitZ();
    const Vector3d centroid = origin;  // base centre
    EXPECT_LT((l.fa - F).norm(), kRel * F.norm());
    EXPECT_LT((l.fb + F).norm(), kRel * F.norm());
    const Vector3d ta = (centroid - ma.position).cross(F);
    const Vector3d tb = (centroid - mb.position).cross(-F);
    EXPECT_LT((l.ta - ta).norm(), kRel * ta.norm());
    EXPECT_LT((l.tb - tb).norm(), kRel * tb.norm());
    // Momentum balance about the world origin.
    const Vector3d total = ma.position.cross(l.fa) + l.ta + mb.position.cross(l.fb) + l.tb;
    EXPECT_LT(total.norm(), kRel * F.norm());
    std::printf("[measured] eccentric statue on pedestal: force error %.1e, torque error A %.1e, "
                "B %.1e (relative)\n", (l.fa - F).norm() / F.norm(), (l.ta - ta).norm() / ta.norm(),
                (l.tb - tb).norm() / tb.norm());
  }
}

TEST(BodyContact, SwappingTheBodiesSwapsTheSides) {
  // A tilted box dug 1 cm into a drum along an edge: both passes see nodes
  // (the penetrated wedge holds some of the drum's top nodes).
  Body a = make_body(Clump(ConvexShape::box({0.3, 0.2, 0.4})), spacing(0.05));
  Body b = make_body(Clump(ConvexShape::prism(0.5, 12, 0.6)), spacing(0.05));
  const Quaterniond qa(AngleAxisd(0.1, Vector3d(0.3, 1, 0).normalized()));
  BodyMotion ma = placed(a, {0.02, 0.03, 0.61}, qa);
  BodyMotion mb = placed(b, Vector3d::Zero(), Quaterniond(AngleAxisd(0.2, Vector3d::UnitZ())));
  ma.velocity = {0.1, 0.2, -0.3};
  ma.angular_velocity = {0.5, -0.2, 0.1};
  mb.angular_velocity = {0.0, 0.1, 0.7};
  const auto ab = contacts(a, ma, b, mb);
  const auto ba = contacts(b, mb, a, ma);
  ASSERT_EQ(ab.size(), ba.size());
  ASSERT_FALSE(of_side(ab, ContactSide::kNodeOfA).empty());
  ASSERT_FALSE(of_side(ab, ContactSide::kNodeOfB).empty());
  std::map<std::pair<int, int>, NodeContact> by;
  for (const auto& c : ba) by[{static_cast<int>(c.side), c.node}] = c;
  for (const auto& c : ab) {
    const int other = c.side == ContactSide::kNodeOfA ? 1 : 0;
    auto it = by.find({other, c.node});
    ASSERT_NE(it, by.end()) << "node " << c.node;
    const NodeContact& d = it->second;
    EXPECT_EQ(c.piece, d.piece);
    EXPECT_EQ(c.face, d.face);
    EXPECT_EQ(c.key ^ 1u, d.key);
    EXPECT_EQ(c.normal, d.normal);
    EXPECT_EQ(c.overlap, d.overlap);
    EXPECT_EQ(c.point, d.point);
    EXPECT_EQ(c.velocity, d.velocity);
    EXPECT_EQ(c.area, d.area);
    EXPECT_EQ(c.lever_a, d.lever_b);
    EXPECT_EQ(c.lever_b, d.lever_a);
    // The same force on the node's body gives the same loads, swapped.
    const Vector3d f(1.0, -2.0, 30.0);
    Vector3d fa = Vector3d::Zero(), ta = fa, fb = fa, tb = fa, ga = fa, sa = fa, gb = fa, sb = fa;
    freestand::apply_node_force(c, f, fa, ta, fb, tb);
    freestand::apply_node_force(d, f, ga, sa, gb, sb);
    EXPECT_EQ(fa, gb);
    EXPECT_EQ(ta, sb);
    EXPECT_EQ(fb, ga);
    EXPECT_EQ(tb, sa);
  }
  std::printf("[measured] tilted box in drum: %zu contacts (%zu of the box, %zu of the drum)\n",
              ab.size(), of_side(ab, ContactSide::kNodeOfA).size(), of_side(ab, ContactSide::kNodeOfB).size());
}

// A pedestal made of two glued half blocks behaves as the whole block: the
// glued faces (+-x at x = 0) are never the way out, and a node over the glue
// line is found once.
TEST(BodyContact, GluedClumpPiecesActAsOneBody) {
  const ConvexShape half = ConvexShape::box({0.25, 0.4, 0.3});
  ClumpPiece left{half, Quaterniond::Identity(), Vector3d(-0.25, 0, 0)};
  ClumpPiece right{half, Quaterniond::Identity(), Vector3d(0.25, 0, 0)};
  NodeOptions none = spacing(0.1);
  none.faces = {FaceRef{0, 0}};
  Body glued = make_body(Clump({left, right}), none);
  Body whole = make_body(Clump(ConvexShape::box({0.5, 0.4, 0.3})), none);
  Body a = make_body(Clump(ConvexShape::box({0.3, 0.2, 0.4})), spacing(0.1));
  const BodyMotion ma = placed(a, {0.0, 0.05, 0.6 - kDelta});  // base nodes at x = 0 lie on the glue plane
  const auto g = contacts(a, ma, glued, placed(glued, Vector3d::Zero()));
  const auto w = contacts(a, ma, whole, placed(whole, Vector3d::Zero()));
  ASSERT_EQ(g.size(), w.size());
  ASSERT_EQ(g.size(), 35u);
  for (std::size_t k = 0; k < g.size(); ++k) {
    EXPECT_EQ(g[k].node, w[k].node);
    EXPECT_EQ(g[k].normal, Vector3d(0, 0, 1));
    EXPECT_NEAR(g[k].overlap, kDelta, kDepthTol);
  }
  // A node 3e-6 m from the glue plane, 1e-5 m deep, with a band of 5e-6 m:
  // were the glued face a way out, the top would leave the band and the node
  // would drop out.
  BodyContactOptions narrow;
  narrow.band = 0.5 * kDelta;
  const BodyMotion shifted = placed(a, {3e-6, 0.05, 0.6 - kDelta});
  EXPECT_EQ(contacts(a, shifted, glued, placed(glued, Vector3d::Zero()), narrow).size(),
            contacts(a, shifted, whole, placed(whole, Vector3d::Zero()), narrow).size());
  EXPECT_EQ(contacts(a, shifted, glued, placed(glued, Vector3d::Zero()), narrow).size(), 35u);
}

TEST(BodyContact, OutputCapacityIsReused) {
  Stack s;
  std::vector<NodeContact> out;
  freestand::find_body_contacts(s.a.model, s.ma, s.b.model, s.mb, {}, out);
  const NodeContact* data = out.data();
  const std::size_t n = out.size();
  for (int i = 0; i < 10; ++i) freestand::find_body_contacts(s.a.model, s.ma, s.b.model, s.mb, {}, out);
  EXPECT_EQ(out.data(), data);
  EXPECT_EQ(out.size(), n);
  freestand::ContactNode bad;
  bad.position = Vector3d::Zero();
  bad.normal = Vector3d::UnitZ();
  bad.area = 1.0;
  bad.face = 9;
  EXPECT_THROW(BodyContactModel(s.a.geometry, s.a.com, {bad}), freestand::InputError);
}

// Timing, not a pass/fail test.
TEST(BodyContact, DISABLED_Bench) {
  const Clump drum(ConvexShape::prism(0.5, 20, 0.6));
  for (double h : {0.1, 0.05}) {
    Body a = make_body(drum, spacing(h)), b = make_body(drum, spacing(h));
    const BodyMotion mb = placed(b, Vector3d::Zero());
    struct Case { const char* name; BodyMotion ma; };
    const Case cases[] = {
        {"resting flush", placed(a, {0, 0, 0.6 - kDelta})},
        {"rocking on rim", placed(a, {0, 0, 0.6 - kDelta + 0.5 * std::cos(kPi / 20) * std::sin(0.02)},
                                  Quaterniond(AngleAxisd(0.02, Vector3d::UnitY())))},
        {"apart (broad phase)", placed(a, {3.0, 0, 0})}};
    std::vector<NodeContact> out;
    for (const Case& c : cases) {
      double best = 1e30;
      for (int rep = 0; rep < 3; ++rep) {
        const int n = 200;
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < n; ++i) freestand::find_body_contacts(a.model, c.ma, b.model, mb, {}, out);
        const auto t1 = std::chrono::steady_clock::now();
        best = std::min(best, std::chrono::duration<double>(t1 - t0).count() / n);
      }
      std::printf("[measured] drums r 0.5 m 20 sides, h = %.2f m (%zu nodes each), %s: %zu contacts, "
                  "%.1f us per pair\n", h, a.model.nodes().size(), c.name, out.size(), best * 1e6);
    }
  }
}
