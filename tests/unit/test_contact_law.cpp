// The contact law of one node (src/freestand/contact_law.h) step by step:
// validation, the normal and tangential equations, the stick/slip state
// machine, history rotation, Newton's third law, frame invariance and the
// per-area convergence of a face's stiffness. Impacts, resting bodies and the
// critical time step are in test_contact_law_dynamics.cpp.
//
// Most checks compare against the equations of docs/contact-law.md evaluated
// independently here; the tolerance is then round-off (1e-12 relative: a few
// dozen floating-point operations), which still catches any wrong factor,
// exponent, sign or state transition.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "freestand/contact_law.h"
#include "freestand/input_error.h"

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using freestand::ContactForce;
using freestand::ContactHistory;
using freestand::ContactLaw;
using freestand::ContactParams;
using freestand::ContactPoint;
using freestand::NormalLaw;

namespace {

constexpr double kRoundOff = 1e-12;

ContactParams linear_params() {
  ContactParams p;
  p.law = NormalLaw::kLinear;
  p.stiffness_per_area = 2e9;  // N/m^3: 1 m^2 of stone on steel, ~0.1 mm under 20 t
  p.damping_ratio = 0.2;
  p.mu_s = 0.6;
  p.mu_k = 0.4;
  return p;
}

ContactParams hertz_params() {
  ContactParams p = linear_params();
  p.law = NormalLaw::kHertz;
  p.hertz_reference_overlap = 1e-4;
  return p;
}

ContactPoint point(const Vector3d& n, double overlap, const Vector3d& v, double area = 0.01,
                   double m_eff = 50.0) {
  ContactPoint c;
  c.normal = n;
  c.overlap = overlap;
  c.velocity = v;
  c.area = area;
  c.effective_mass = m_eff;
  return c;
}

void expect_vec_near(const Vector3d& a, const Vector3d& b, double tol, const std::string& what) {
  EXPECT_LE((a - b).norm(), tol) << what << ": " << a.transpose() << " vs " << b.transpose();
}

}  // namespace

// ---------------------------------------------------------------------------
// Parameters

TEST(ContactLawValidation, AcceptsAWellFormedInterface) {
  EXPECT_NO_THROW(ContactLaw{linear_params()});
  EXPECT_NO_THROW(ContactLaw{hertz_params()});
  ContactParams p = linear_params();
  p.damping_ratio.reset();
  p.restitution = 0.5;
  const ContactLaw law(p);
  EXPECT_NEAR(law.restitution(), 0.5, 1e-13);
}

TEST(ContactLawValidation, RejectsBadParametersNamingThem) {
  struct Case {
    std::function<void(ContactParams&)> edit;
    std::string expect;  // must appear in the message
  };
  const std::vector<Case> cases = {
      {[](ContactParams& p) { p.stiffness_per_area = -1.0; }, "stiffness_per_area"},
      {[](ContactParams& p) { p.stiffness_per_area = 0.0; }, "stiffness_per_area"},
      {[](ContactParams& p) { p.stiffness_per_area = NAN; }, "stiffness_per_area"},
      {[](ContactParams& p) { p.law = NormalLaw::kHertz; }, "hertz_reference_overlap"},
      {[](ContactParams& p) {
         p.law = NormalLaw::kHertz;
         p.hertz_reference_overlap = -1e-4;
       },
       "hertz_reference_overlap"},
      {[](ContactParams& p) { p.damping_ratio = -0.1; }, "damping_ratio"},
      {[](ContactParams& p) { p.restitution = 0.5; }, "not both"},
      {[](ContactParams& p) { p.damping_ratio.reset(); }, "damping_ratio or restitution"},
      {[](ContactParams& p) {
         p.damping_ratio.reset();
         p.restitution = 0.0;
       },
       "restitution must be in (0, 1]"},
      {[](ContactParams& p) {
         p.damping_ratio.reset();
         p.restitution = 1.2;
       },
       "restitution must be in (0, 1]"},
      {[](ContactParams& p) { p.tangential_stiffness_ratio = 0.0; }, "tangential_stiffness_ratio"},
      {[](ContactParams& p) { p.tangential_damping_ratio = -1.0; }, "tangential_damping_ratio"},
      {[](ContactParams& p) { p.mu_s = NAN; }, "mu_s is not set"},
      {[](ContactParams& p) { p.mu_k = NAN; }, "mu_k is not set"},
      {[](ContactParams& p) { p.mu_s = -0.1; }, "mu_s"},
      {[](ContactParams& p) { p.mu_k = 0.7; }, "mu_k (0.7) must not exceed mu_s (0.6)"},
      {[](ContactParams& p) { p.friction_decay = -2.0; }, "friction_decay"},
  };
  for (const Case& c : cases) {
    ContactParams p = linear_params();
    c.edit(p);
    try {
      ContactLaw law(p);
      ADD_FAILURE() << "no error; expected one mentioning '" << c.expect << "'";
    } catch (const freestand::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.expect), std::string::npos)
          << "message '" << e.what() << "' does not mention '" << c.expect << "'";
    }
  }
}

// ---------------------------------------------------------------------------
// Normal law

TEST(ContactNormal, LinearSpringAndDashpot) {
  const ContactLaw law(linear_params());
  const double A = 0.01, m = 50.0, delta = 2e-5, vn = -0.03;  // approaching
  ContactHistory h;
  const ContactForce f = law.compute(point(Vector3d::UnitZ(), delta, Vector3d(0, 0, vn), A, m), 1e-5, h);
  const double k = 2e9 * A;
  const double expected = k * delta + 2.0 * 0.2 * std::sqrt(k * m) * (-vn);
  EXPECT_NEAR(f.normal, expected, kRoundOff * expected);
  expect_vec_near(f.force, expected * Vector3d::UnitZ(), kRoundOff * expected, "force");
  EXPECT_FALSE(f.sliding);
}

TEST(ContactNormal, HertzPerAreaForm) {
  const ContactLaw law(hertz_params());
  const double A = 0.01, m = 50.0, dref = 1e-4, ka = 2e9;
  ContactHistory h;
  // Elastic part: F = k_a A delta^{3/2} / sqrt(delta_ref), equal to the
  // linear law's k_a A delta at delta = delta_ref.
  for (double delta : {1e-6, 3e-5, 1e-4, 4e-4}) {
    const ContactForce f = law.compute(point(Vector3d::UnitZ(), delta, Vector3d::Zero(), A, m), 1e-5, h);
    const double expected = ka * A * std::pow(delta, 1.5) / std::sqrt(dref);
    EXPECT_NEAR(f.normal, expected, kRoundOff * expected) << delta;
  }
  EXPECT_NEAR(law.elastic_force(A, dref), ka * A * dref, kRoundOff * ka * A * dref);
  // Tsuji dashpot: sqrt(5) zeta sqrt(k_h A m) delta^{1/4} ddelta/dt.
  const double delta = 5e-5, rate = 0.02;
  const ContactForce f =
      law.compute(point(Vector3d::UnitZ(), delta, Vector3d(0, 0, -rate), A, m), 1e-5, h);
  const double kh = ka / std::sqrt(dref);
  const double expected = kh * A * std::pow(delta, 1.5) +
                          std::sqrt(5.0) * 0.2 * std::sqrt(kh * A * m) * std::pow(delta, 0.25) * rate;
  EXPECT_NEAR(f.normal, expected, kRoundOff * expected);
  // Mindlin: k_t = kappa * (tangent normal stiffness) = kappa 1.5 k_h A delta^{1/2}.
  ContactHistory fresh;
  const double vt = 1e-3, dt = 1e-6;
  const ContactForce g =
      law.compute(point(Vector3d::UnitZ(), delta, Vector3d(vt, 0, 0), A, m), dt, fresh);
  const double kt = 6.0 / 7.0 * 1.5 * kh * A * std::sqrt(delta);
  ASSERT_FALSE(g.sliding);
  EXPECT_NEAR(g.tangential.x(), -kt * vt * dt, kRoundOff * kt * vt * dt);
}

TEST(ContactNormal, NeverAttractive) {
  for (const ContactParams& p : {linear_params(), hertz_params()}) {
    const ContactLaw law(p);
    ContactHistory h;
    h.xi[0] = 1e-7;  // a loaded tangential spring
    // Separating faster than the spring can push: the dashpot would pull.
    const ContactForce f =
        law.compute(point(Vector3d::UnitZ(), 1e-6, Vector3d(0.01, 0, 5.0)), 1e-5, h);
    EXPECT_EQ(f.normal, 0.0);
    EXPECT_EQ(f.force.norm(), 0.0) << "no friction without normal force";
    EXPECT_TRUE(f.sliding);
  }
}

TEST(ContactNormal, NoOverlapIsNoForceAndForgetsHistory) {
  const ContactLaw law(linear_params());
  ContactHistory h;
  h.xi[1] = 3e-6;
  h.sliding = 1.0;
  const ContactForce f = law.compute(point(Vector3d::UnitZ(), -1e-6, Vector3d(0, 0.1, -1)), 1e-5, h);
  EXPECT_EQ(f.force.norm(), 0.0);
  EXPECT_EQ(h.displacement().norm(), 0.0);
  EXPECT_FALSE(h.is_sliding());
}

// ---------------------------------------------------------------------------
// Tangential law and friction

TEST(ContactTangential, StickIsElasticAndReturnsToZero) {
  ContactParams p = linear_params();
  p.damping_ratio = 0.0;
  const ContactLaw law(p);
  const double A = 0.01, delta = 1e-5, dt = 1e-5, v = 1e-4;
  const double fn = 2e9 * A * delta;
  const double kt = freestand::kDefaultTangentialStiffnessRatio * 2e9 * A;
  ContactHistory h;
  // 50 steps forward: xi = 50 v dt = 5e-8 m, F_t = k_t xi = 0.5 mu_s F_n.
  ContactForce f;
  for (int i = 0; i < 50; ++i)
    f = law.compute(point(Vector3d::UnitZ(), delta, Vector3d(v, 0, 0), A), dt, h);
  ASSERT_FALSE(f.sliding);
  const double peak = kt * 50 * v * dt;
  EXPECT_LT(peak, 0.6 * fn);
  expect_vec_near(f.tangential, Vector3d(-peak, 0, 0), kRoundOff * peak, "loaded spring");
  // 50 steps back: the spring unloads along the same line to zero.
  for (int i = 0; i < 50; ++i)
    f = law.compute(point(Vector3d::UnitZ(), delta, Vector3d(-v, 0, 0), A), dt, h);
  EXPECT_LE(f.tangential.norm(), kRoundOff * peak);
  EXPECT_FALSE(f.sliding);
}

TEST(ContactTangential, DashpotActsWhileStuck) {
  ContactParams p = linear_params();
  p.tangential_damping_ratio = 0.1;
  const ContactLaw law(p);
  const double A = 0.01, m = 50.0, delta = 1e-5, dt = 1e-5, v = 1e-4;
  ContactHistory h;
  const ContactForce f = law.compute(point(Vector3d::UnitZ(), delta, Vector3d(0, v, 0), A, m), dt, h);
  const double kt = freestand::kDefaultTangentialStiffnessRatio * 2e9 * A;
  const double expected = kt * v * dt + 2.0 * 0.1 * std::sqrt(kt * m) * v;
  ASSERT_FALSE(f.sliding);
  expect_vec_near(f.tangential, Vector3d(0, -expected, 0), kRoundOff * expected, "spring + dashpot");
}

TEST(ContactFriction, SlipsAtExactlyMuStaticThenKinetic) {
  ContactParams p = linear_params();
  p.damping_ratio = 0.0;
  const ContactLaw law(p);
  const double A = 0.01, delta = 1e-5, dt = 1e-5, v = 1e-3;
  const double fn = 2e9 * A * delta;
  ContactHistory h;
  double previous = 0.0;
  int breakaway = -1;
  for (int i = 0; i < 2000 && breakaway < 0; ++i) {
    const ContactForce f = law.compute(point(Vector3d::UnitZ(), delta, Vector3d(v, 0, 0), A), dt, h);
    const double ft = f.tangential.norm();
    if (f.sliding) {
      breakaway = i;
      // The breakaway step carries exactly the static limit...
      EXPECT_NEAR(ft, 0.6 * fn, kRoundOff * fn);
      EXPECT_GT(previous + 2e9 * A * 6.0 / 7.0 * v * dt, 0.6 * fn) << "trial force exceeded mu_s F_n";
      // ...and the spring is reset to it: |k_t xi| = mu_s F_n, opposing the motion.
      const double kt = 6.0 / 7.0 * 2e9 * A;
      EXPECT_NEAR(kt * h.displacement().norm(), 0.6 * fn, kRoundOff * fn);
      EXPECT_GT(h.displacement().x(), 0.0);
    } else {
      EXPECT_LE(ft, 0.6 * fn * (1 + kRoundOff)) << "stuck above mu_s F_n at step " << i;
      previous = ft;
    }
  }
  ASSERT_GT(breakaway, 0);
  // Afterwards: kinetic friction, opposing the sliding velocity.
  for (int i = 0; i < 10; ++i) {
    const ContactForce f = law.compute(point(Vector3d::UnitZ(), delta, Vector3d(v, 0, 0), A), dt, h);
    EXPECT_TRUE(f.sliding);
    expect_vec_near(f.tangential, Vector3d(-0.4 * fn, 0, 0), kRoundOff * fn, "kinetic friction");
  }
}

TEST(ContactFriction, RestickStateMachine) {
  ContactParams p = linear_params();
  p.damping_ratio = 0.0;
  const ContactLaw law(p);
  const double A = 0.01, delta = 1e-5, dt = 1e-5, v = 1e-3;
  const double fn = 2e9 * A * delta;
  const double kt = 6.0 / 7.0 * 2e9 * A;
  const Vector3d n = Vector3d::UnitZ();
  auto step = [&](ContactHistory& h, const Vector3d& vel) {
    return law.compute(point(n, delta, vel, A), dt, h);
  };
  ContactHistory sliding;
  for (int i = 0; i < 1000; ++i) step(sliding, Vector3d(v, 0, 0));
  ASSERT_TRUE(sliding.is_sliding());

  // 1. Sliding stops (v_t = 0): the trial force equals mu_k F_n, on the
  //    kinetic cone, so the contact re-sticks holding mu_k F_n...
  ContactHistory h = sliding;
  ContactForce f = step(h, Vector3d::Zero());
  EXPECT_FALSE(f.sliding);
  EXPECT_NEAR(f.tangential.norm(), 0.4 * fn, kRoundOff * fn);
  //    ...and needs mu_s F_n again to break away: load it back in +x.
  int steps_to_break = 0;
  for (; steps_to_break < 1000; ++steps_to_break) {
    f = step(h, Vector3d(v, 0, 0));
    if (f.sliding) break;
    EXPECT_LE(f.tangential.norm(), 0.6 * fn * (1 + kRoundOff));
  }
  EXPECT_NEAR(f.tangential.norm(), 0.6 * fn, kRoundOff * fn);
  // (0.6 - 0.4) F_n of extra spring load at k_t v dt per step.
  EXPECT_EQ(steps_to_break, static_cast<int>(std::floor(0.2 * fn / (kt * v * dt))));

  // 2. Sliding reverses: the spring unloads elastically at once (stuck).
  h = sliding;
  f = step(h, Vector3d(-v, 0, 0));
  EXPECT_FALSE(f.sliding);
  EXPECT_NEAR(f.tangential.x(), -0.4 * fn + kt * v * dt, kRoundOff * fn);

  // 3. Sliding continues ever more slowly in the same direction: the trial
  //    force stays outside the cone, so it keeps sliding (no speed threshold).
  h = sliding;
  for (double speed : {1e-4, 1e-6, 1e-9}) {
    f = step(h, Vector3d(speed, 0, 0));
    EXPECT_TRUE(f.sliding) << speed;
  }
  // 4. Sideways turn while sliding: force follows the trial direction.
  h = sliding;
  f = step(h, Vector3d(0, v, 0));
  EXPECT_TRUE(f.sliding);
  EXPECT_NEAR(f.tangential.norm(), 0.4 * fn, kRoundOff * fn);
  const Vector3d trial = -kt * (sliding.displacement() + Vector3d(0, v, 0) * dt);
  expect_vec_near(f.tangential.normalized(), trial.normalized(), 1e-12, "direction of trial force");
}

TEST(ContactFriction, VelocityDependentMuMatchesFormula) {
  ContactParams p = linear_params();
  p.damping_ratio = 0.0;
  p.friction_decay = 8.0;  // s/m
  const ContactLaw law(p);
  const double A = 0.01, delta = 1e-5, dt = 1e-5;
  const double fn = 2e9 * A * delta;
  for (double speed : {0.001, 0.01, 0.05, 0.1, 0.3, 1.0}) {
    // From rest: load the spring until it breaks away, then slide 3 steps.
    ContactHistory h;
    const Vector3d vel = speed * Vector3d(0.6, 0.8, 0);
    ContactForce f;
    int i = 0;
    for (; i < 100000 && !f.sliding; ++i) f = law.compute(point(Vector3d::UnitZ(), delta, vel, A), dt, h);
    ASSERT_TRUE(f.sliding) << speed;
    for (int k = 0; k < 3; ++k) f = law.compute(point(Vector3d::UnitZ(), delta, vel, A), dt, h);
    ASSERT_TRUE(f.sliding) << speed;
    const double mu = 0.4 + (0.6 - 0.4) * std::exp(-8.0 * speed);
    EXPECT_NEAR(f.tangential.norm() / fn, mu, 1e-12) << speed;
    EXPECT_NEAR(law.kinetic_friction(speed), mu, 1e-15);
    expect_vec_near(f.tangential.normalized(), -vel.normalized(), 1e-9, "opposes sliding");
  }
  // d_c = 0 is the plain switch: mu_k at any speed.
  p.friction_decay = 0.0;
  EXPECT_EQ(ContactLaw(p).kinetic_friction(1e-9), 0.4);
}

// ---------------------------------------------------------------------------
// History rotation

TEST(ContactHistoryRotation, KeepsMagnitudeInTheNewTangentPlane) {
  const Vector3d xi(3e-6, -1e-6, 0.0);  // in the plane of n0 = z
  for (double angle : {1e-6, 0.01, 0.3, 1.2}) {
    const Vector3d axis = Vector3d(1, 2, 0.5).normalized();
    const Vector3d n = AngleAxisd(angle, axis) * Vector3d::UnitZ();
    const Vector3d r = freestand::rotate_into_tangent_plane(xi, n);
    EXPECT_NEAR(r.norm(), xi.norm(), 1e-15 * xi.norm() * 10) << angle;
    EXPECT_LE(std::abs(r.dot(n)), 1e-15 * xi.norm() * 10) << angle;
    // It is the projection, rescaled: same direction as xi - (xi.n) n.
    EXPECT_NEAR(r.normalized().dot((xi - xi.dot(n) * n).normalized()), 1.0, 1e-14);
  }
  // Parallel to the new normal: nothing to keep.
  EXPECT_EQ(freestand::rotate_into_tangent_plane(Vector3d(0, 0, 2e-6), Vector3d::UnitZ()).norm(), 0.0);

  // Through compute(): with no tangential motion a stuck spring only turns.
  ContactParams p = linear_params();
  p.mu_s = p.mu_k = 100.0;
  const ContactLaw law(p);
  ContactHistory h;
  h.xi[0] = xi.x();
  h.xi[1] = xi.y();
  const Vector3d n = AngleAxisd(0.4, Vector3d::UnitX()) * Vector3d::UnitZ();
  const ContactForce f = law.compute(point(n, 1e-5, Vector3d::Zero()), 1e-5, h);
  EXPECT_NEAR(h.displacement().norm(), xi.norm(), 1e-14 * xi.norm());
  EXPECT_LE(std::abs(h.displacement().dot(n)), 1e-14 * xi.norm());
  EXPECT_LE(std::abs(f.tangential.dot(n)), 1e-12 * f.tangential.norm());
}

// ---------------------------------------------------------------------------
// Symmetry

TEST(ContactSymmetry, NewtonsThirdLawWhenRolesSwap) {
  // The same contact seen from the other body: normal and relative velocity
  // change sign, and so does the history. The force must be the opposite, at
  // every step, through stick, breakaway and sliding.
  for (const ContactParams& base : {linear_params(), hertz_params()}) {
    ContactParams p = base;
    p.tangential_damping_ratio = 0.05;
    p.friction_decay = 3.0;
    const ContactLaw law(p);
    ContactHistory ha, hb;
    bool slid = false;
    const Vector3d n0 = Vector3d(0.2, -0.1, 1.0).normalized();
    for (int i = 0; i < 300; ++i) {
      const double t = i * 1e-5;
      const Vector3d n = AngleAxisd(0.3 * t * 1e3, Vector3d::UnitY()) * n0;  // turning normal
      const Vector3d v(0.1 * std::cos(900 * t), 0.05, -1e-3 * std::sin(500 * t));
      const double delta = 2e-5 * (1.0 + 0.5 * std::sin(700 * t));
      const ContactForce fa = law.compute(point(n, delta, v), 1e-5, ha);
      const ContactForce fb = law.compute(point(-n, delta, -v), 1e-5, hb);
      expect_vec_near(fa.force, -fb.force, 1e-12 * fa.force.norm(), "step " + std::to_string(i));
      EXPECT_EQ(fa.sliding, fb.sliding);
      slid = slid || fa.sliding;
    }
    EXPECT_TRUE(slid) << "the sequence should exercise sliding too";
  }
}

TEST(ContactSymmetry, RotatingTheConfigurationRotatesTheForce) {
  const Matrix3d R = (AngleAxisd(0.7, Vector3d(1, -2, 3).normalized()) *
                      AngleAxisd(-1.1, Vector3d::UnitX())).toRotationMatrix();
  for (const ContactParams& base : {linear_params(), hertz_params()}) {
    ContactParams p = base;
    p.tangential_damping_ratio = 0.05;
    const ContactLaw law(p);
    ContactHistory h, hr;
    bool slid = false;
    for (int i = 0; i < 300; ++i) {
      const double t = i * 1e-5;
      const Vector3d n = AngleAxisd(200 * t, Vector3d::UnitX()) * Vector3d::UnitZ();
      const Vector3d v(0.1 * std::cos(800 * t), 0.08 * std::sin(300 * t), -1e-3);
      const double delta = 1e-5 * (1.2 + std::sin(600 * t));
      const ContactForce f = law.compute(point(n, delta, v), 1e-5, h);
      const ContactForce fr = law.compute(point(R * n, delta, R * v), 1e-5, hr);
      expect_vec_near(fr.force, R * f.force, 1e-12 * f.force.norm(), "step " + std::to_string(i));
      expect_vec_near(hr.displacement(), R * h.displacement(), 1e-12 * h.displacement().norm() + 1e-30,
                      "history");
      slid = slid || f.sliding;
    }
    EXPECT_TRUE(slid) << "the sequence should exercise sliding too";
  }
}

// ---------------------------------------------------------------------------
// Convergence with the node grid

namespace {
// A square face of side L sampled by an n x n grid of cell centres, each with
// tributary area (L/n)^2.
struct Grid {
  std::vector<Vector3d> points;
  std::vector<double> areas;
};
Grid square_grid(double L, int n) {
  Grid g;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      g.points.emplace_back(L * ((i + 0.5) / n - 0.5), L * ((j + 0.5) / n - 0.5), 0.0);
      g.areas.push_back(L * L / (n * n));
    }
  return g;
}
}  // namespace

TEST(ContactConvergence, FaceStiffnessIndependentOfNodeCount) {
  // Whole face at uniform overlap: the total force, stiffness and dashpot of
  // the face are sums over nodes and must not depend on the count.
  const double L = 0.6, M = 1200.0, A_face = L * L;
  for (const ContactParams& p : {linear_params(), hertz_params()}) {
    const ContactLaw law(p);
    const double delta = 3e-5;
    double reference_force = 0, reference_stiffness = 0, reference_damping = 0;
    for (int n : {2, 4, 8}) {  // 4, 16, 64 nodes
      const Grid g = square_grid(L, n);
      double force = 0, stiffness = 0, damping = 0;
      for (std::size_t i = 0; i < g.points.size(); ++i) {
        ContactHistory h;
        const double m_eff = M * g.areas[i] / A_face;
        force += law.compute(point(Vector3d::UnitZ(), delta, Vector3d::Zero(), g.areas[i], m_eff),
                             1e-5, h).normal;
        const auto lin = law.linearize(g.areas[i], m_eff, delta);
        stiffness += lin.normal_stiffness;
        damping += lin.normal_damping;
      }
      if (n == 2) {
        reference_force = force;
        reference_stiffness = stiffness;
        reference_damping = damping;
        // ... and equal to the closed form of the whole face.
        const double expected = p.law == NormalLaw::kLinear
                                    ? 2e9 * A_face * delta
                                    : 2e9 * A_face * std::pow(delta, 1.5) / std::sqrt(1e-4);
        EXPECT_NEAR(force, expected, 1e-13 * expected);
        const auto face = law.linearize(A_face, M, delta);
        EXPECT_NEAR(stiffness, face.normal_stiffness, 1e-13 * stiffness);
        EXPECT_NEAR(damping, face.normal_damping, 1e-13 * damping);
      }
      EXPECT_NEAR(force, reference_force, 1e-13 * reference_force) << n * n << " nodes";
      EXPECT_NEAR(stiffness, reference_stiffness, 1e-13 * reference_stiffness) << n * n << " nodes";
      EXPECT_NEAR(damping, reference_damping, 1e-13 * reference_damping) << n * n << " nodes";
    }
  }
}

TEST(ContactConvergence, TiltedFaceForceAndMomentConverge) {
  // A face pressed with a wedge-shaped overlap delta(x) = d0 + s x, the state
  // of a rocking block. Linear law, whole face in contact: force and moment
  // are integrals of polynomials, so the node sums converge at second order
  // to k_a L^2 d0 and k_a L^4 s / 12. Partly lifted (heel in contact only)
  // the only error is the column of cells straddling the lift-off line,
  // O(h^2) as well; the test asks for monotone convergence below 1 %.
  const ContactLaw law(linear_params());
  const double L = 0.6, ka = 2e9;
  auto sums = [&](int n, double d0, double s) {
    const Grid g = square_grid(L, n);
    double force = 0, moment = 0;
    for (std::size_t i = 0; i < g.points.size(); ++i) {
      ContactHistory h;
      const double x = g.points[i].x();
      const double f =
          law.compute(point(Vector3d::UnitZ(), d0 + s * x, Vector3d::Zero(), g.areas[i]), 1e-5, h).normal;
      force += f;
      moment += x * f;
    }
    return std::make_pair(force, moment);
  };
  // Full contact.
  const double d0 = 4e-5, s = 1e-4;
  double previous_moment_error = 0;
  for (int n : {2, 4, 8, 16}) {
    const auto [force, moment] = sums(n, d0, s);
    const double exact_force = ka * L * L * d0, exact_moment = ka * std::pow(L, 4) * s / 12.0;
    EXPECT_NEAR(force, exact_force, 1e-12 * exact_force) << n;  // midpoint rule: exact for linear
    const double err = std::abs(moment - exact_moment) / exact_moment;
    // Midpoint rule on x^2 over n cells: relative error exactly 1/n^2.
    EXPECT_NEAR(err, 1.0 / (n * n), 1e-10) << n;
    if (previous_moment_error > 0) EXPECT_NEAR(previous_moment_error / err, 4.0, 1e-6);
    previous_moment_error = err;
    std::printf("[measured] tilted face, full contact, %3d nodes: moment error %.3e\n", n * n, err);
  }
  // Heel only: delta = s (x - x0) for x > x0, x0 = 0.1 m.
  const double x0 = 0.1;
  const double exact_force = ka * L * s * std::pow(L / 2 - x0, 2) / 2.0;
  double previous_error = 0;
  for (int n : {4, 16, 64, 256}) {
    const double err = std::abs(sums(n, -s * x0, s).first - exact_force) / exact_force;
    std::printf("[measured] tilted face, heel contact, %5d nodes: force error %.3e\n", n * n, err);
    if (previous_error > 0) EXPECT_LT(err, 0.6 * previous_error) << n;
    previous_error = err;
  }
  EXPECT_LT(previous_error, 1e-2);
}

// ---------------------------------------------------------------------------
// Restitution mapping (closed form; impacts are simulated in the dynamics tests)

TEST(ContactRestitution, ClampedMappingBranchesAndInverse) {
  // zeta = 1 separates the branches: e = exp(-2) from both sides.
  EXPECT_NEAR(freestand::restitution_from_damping_ratio(1.0), std::exp(-2.0), 1e-15);
  EXPECT_NEAR(freestand::restitution_from_damping_ratio(1.0 - 1e-9), std::exp(-2.0), 1e-8);
  EXPECT_NEAR(freestand::restitution_from_damping_ratio(1.0 + 1e-9), std::exp(-2.0), 1e-8);
  EXPECT_EQ(freestand::restitution_from_damping_ratio(0.0), 1.0);
  // Small zeta: both forms agree to first order, e ~ 1 - pi zeta.
  EXPECT_NEAR(freestand::restitution_from_damping_ratio(1e-6), 1.0 - M_PI * 1e-6, 1e-11);
  // Decreasing; huge zeta still gives a positive e ~ 1/(4 zeta^2).
  double previous = 1.0;
  for (double z = 0.01; z < 1e6; z *= 1.3) {
    const double e = freestand::restitution_from_damping_ratio(z);
    EXPECT_LT(e, previous) << z;
    previous = e;
  }
  EXPECT_NEAR(freestand::restitution_from_damping_ratio(1e4) * 4e8, 1.0, 1e-3);
  // Inverse.
  for (double e : {1.0, 0.999, 0.9, 0.5, 0.2, std::exp(-2.0), 0.1, 0.01, 1e-6}) {
    const double z = freestand::damping_ratio_from_restitution(e);
    EXPECT_NEAR(freestand::restitution_from_damping_ratio(z), e, 1e-13 * e) << e;
  }
  // Tabulated values quoted in docs/contact-law.md.
  EXPECT_NEAR(freestand::damping_ratio_from_restitution(0.5), 0.25528, 5e-6);
  EXPECT_NEAR(freestand::damping_ratio_from_restitution(0.1), 1.24319, 5e-6);
  EXPECT_NEAR(freestand::unclamped_restitution(0.2155), 0.5, 1e-4);
}
