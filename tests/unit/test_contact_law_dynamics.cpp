// The contact law (src/freestand/contact_law.h) inside time integration:
// single-dof impacts against the restitution mapping, a block of nodes
// settling under gravity against the closed-form static overlap, and the
// critical time step (src/freestand/contact_time_step.h) against simulations
// just below and just above it.
//
// Every simulation here integrates the way LIGGGHTS does (velocity Verlet:
// half kick, drift, forces from the new positions and the HALF-STEP
// velocities, half kick), so what is measured is what a run will see.
// Lines starting with [measured] are the numbers quoted in docs/contact-law.md.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "freestand/contact_law.h"
#include "freestand/contact_time_step.h"
#include "freestand/input_error.h"

using Eigen::Matrix3d;
using Eigen::Vector3d;
using freestand::ContactBody;
using freestand::ContactForce;
using freestand::ContactHistory;
using freestand::ContactLaw;
using freestand::ContactParams;
using freestand::ContactPoint;
using freestand::NormalLaw;

namespace {

constexpr double kGravity = 9.81;

ContactParams params(NormalLaw law, double restitution) {
  ContactParams p;
  p.law = law;
  p.stiffness_per_area = 2e9;
  if (law == NormalLaw::kHertz) p.hertz_reference_overlap = 1e-5;
  p.restitution = restitution;
  p.mu_s = 0.6;
  p.mu_k = 0.5;
  return p;
}

ContactPoint vertical_point(double overlap, double vz, double area, double m_eff) {
  ContactPoint c;
  c.normal = Vector3d::UnitZ();
  c.overlap = overlap;
  c.velocity = Vector3d(0, 0, vz);
  c.area = area;
  c.effective_mass = m_eff;
  return c;
}

// ---------------------------------------------------------------------------
// Single-dof impact: a mass m on one node of area A falls at v0 onto the plane
// z = 0, first touching it at t = 0. Returns the outgoing/incoming speed ratio
// measured at the first step after separation (the force is then zero, so
// the speed no longer changes).
struct Impact {
  double restitution = 0;
  double max_overlap = 0;
  int contact_steps = 0;
};

Impact impact(const ContactLaw& law, double m, double A, double v0, double dt) {
  double z = 0.0, v = -v0, f = 0.0;
  ContactHistory h;
  Impact out;
  for (long i = 0; i < 100000000L; ++i) {
    v += 0.5 * dt * f / m;
    z += dt * v;
    f = law.compute(vertical_point(-z, v, A, m), dt, h).force.z();
    v += 0.5 * dt * f / m;
    if (z < 0.0) {
      ++out.contact_steps;
      out.max_overlap = std::max(out.max_overlap, -z);
    } else if (out.contact_steps > 0) {
      out.restitution = v / v0;
      return out;
    }
  }
  ADD_FAILURE() << "impact did not end";
  return out;
}

// Half period of the linearised contact at the largest overlap of an impact:
// the shortest time scale the integration must resolve.
double contact_time_scale(const ContactLaw& law, double m, double A, double v0) {
  const double delta = law.impact_overlap(A, m, v0);
  return M_PI / std::sqrt(law.linearize(A, m, delta).normal_stiffness / m);
}

}  // namespace

// Tolerance: velocity Verlet evaluates the dashpot with the half-step
// velocity, an O(zeta omega dt) error in the dissipated energy; at 20000
// steps per half period (omega dt = 1.6e-4) that is < 1e-4 in e, and the
// start/end of contact falls between steps, another O(omega dt). 1e-3 is ten
// times the measured worst error and ~100 times smaller than the effect of the
// tensile clamp (ContactImpact.ClampRaisesRestitution).
TEST(ContactImpact, LinearRestitutionMatchesTarget) {
  const double m = 100.0, A = 0.05, v0 = 0.5;
  for (double e : {0.95, 0.8, 0.5, 0.3, 0.1, 0.05}) {
    const ContactLaw law(params(NormalLaw::kLinear, e));
    const double dt = contact_time_scale(law, m, A, v0) / 20000.0;
    const Impact r = impact(law, m, A, v0, dt);
    std::printf("[measured] linear e = %.2f (zeta %.5f): measured %.6f, error %+.1e\n", e,
                law.damping_ratio(), r.restitution, r.restitution - e);
    EXPECT_NEAR(r.restitution, e, 1e-3) << "target " << e;
  }
}

TEST(ContactImpact, HertzRestitutionMatchesTargetAtAnySpeed) {
  // The Tsuji dashpot makes e independent of the impact speed; the clamped
  // mapping zeta(e) is exact (docs/contact-law.md), so only integration error
  // remains (same budget as the linear case).
  const double m = 100.0, A = 0.05;
  for (double e : {0.95, 0.8, 0.5, 0.3, 0.1, 0.05}) {
    const ContactLaw law(params(NormalLaw::kHertz, e));
    for (double v0 : {0.02, 0.5, 3.0}) {
      const double dt = contact_time_scale(law, m, A, v0) / 20000.0;
      const Impact r = impact(law, m, A, v0, dt);
      std::printf("[measured] Hertz  e = %.2f v0 = %4.2f m/s: measured %.6f, error %+.1e\n", e, v0,
                  r.restitution, r.restitution - e);
      EXPECT_NEAR(r.restitution, e, 1e-3) << "target " << e << " at " << v0 << " m/s";
    }
  }
}

TEST(ContactImpact, ClampRaisesRestitutionAboveTextbookFormula) {
  // zeta from the textbook e = exp(-pi zeta / sqrt(1 - zeta^2)), which
  // assumes the dashpot may pull at the end of the contact. With the clamp
  // the contact ends earlier and returns more energy.
  const double m = 100.0, A = 0.05, v0 = 0.5;
  for (double e_textbook : {0.9, 0.5, 0.2}) {
    const double l = std::log(e_textbook);
    ContactParams p = params(NormalLaw::kLinear, 1.0);
    p.restitution.reset();
    p.damping_ratio = -l / std::sqrt(M_PI * M_PI + l * l);
    const ContactLaw law(p);
    EXPECT_NEAR(freestand::unclamped_restitution(*p.damping_ratio), e_textbook, 1e-12);
    const double dt = contact_time_scale(law, m, A, v0) / 20000.0;
    const Impact r = impact(law, m, A, v0, dt);
    const double clamped = freestand::restitution_from_damping_ratio(*p.damping_ratio);
    std::printf("[measured] zeta %.4f: textbook e %.3f, clamped formula %.4f, measured %.4f\n",
                *p.damping_ratio, e_textbook, clamped, r.restitution);
    EXPECT_NEAR(r.restitution, clamped, 1e-3);
    EXPECT_GT(r.restitution - e_textbook, 0.002);
  }
}

TEST(ContactImpact, RestitutionErrorVersusTimeStep) {
  // How coarse may dt be? Measured against the critical step of the contact
  // (at the impact's largest overlap for Hertz). Supports
  // recommended_time_step_fraction (0.02 linear, 0.1 Hertz): error below 1 %
  // there. The error is a first-order bias (halving dt halves it), from the
  // half-step velocity that LIGGGHTS' velocity Verlet gives the dashpot.
  const double m = 100.0, A = 0.05, v0 = 0.5;
  for (NormalLaw kind : {NormalLaw::kLinear, NormalLaw::kHertz}) {
    for (double e : {0.9, 0.5, 0.2}) {
      const ContactLaw law(params(kind, e));
      const double overlap = law.impact_overlap(A, m, v0);
      const double dt_crit = freestand::face_critical_time_step(law, A, m, overlap);
      for (double fraction : {0.01, 0.02, 0.05, 0.1, 0.2, 0.5}) {
        const Impact r = impact(law, m, A, v0, fraction * dt_crit);
        std::printf("[measured] %s e = %.1f dt = %.2f dt_crit: %4d steps in contact, e %.4f, "
                    "error %+.2f %%\n",
                    kind == NormalLaw::kLinear ? "linear" : "Hertz ", e, fraction,
                    r.contact_steps, r.restitution, 100.0 * (r.restitution - e) / e);
        if (fraction <= freestand::recommended_time_step_fraction(law) + 1e-12) {
          EXPECT_LT(std::abs(r.restitution - e), 0.01 * e) << "dt = " << fraction << " dt_crit";
          EXPECT_GE(r.contact_steps, 15);
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------
// A rigid block on a grid of base nodes, moving in the x-z plane (x, z, and
// rotation theta about y), on the plane z = 0.

namespace {

struct Block {
  double b = 0.3, d = 0.3, h = 0.4;  // half extents; base face at z = -h from the COM
  double mass = 0.0;
  int n = 6;  // n x n base nodes at cell centres
  std::vector<Vector3d> r;  // node positions relative to the COM, body frame
  std::vector<double> areas;

  Block(double b_, double d_, double h_, double density, int n_) : b(b_), d(d_), h(h_), n(n_) {
    mass = density * 8 * b * d * h;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        r.emplace_back(b * (2.0 * (i + 0.5) / n - 1.0), d * (2.0 * (j + 0.5) / n - 1.0), -h);
        areas.push_back(4 * b * d / (n * n));
      }
  }
  double face_area() const { return 4 * b * d; }
  Matrix3d inertia() const {  // about the COM
    return Vector3d(mass * (d * d + h * h) / 3, mass * (b * b + h * h) / 3,
                    mass * (b * b + d * d) / 3).asDiagonal();
  }
};

struct PlanarState {
  double x = 0, z = 0, theta = 0, vx = 0, vz = 0, w = 0;
};

struct PlanarLoad {
  double fx = 0, fz = 0, torque = 0;
  int sliding = 0;
};

PlanarLoad block_forces(const ContactLaw& law, const Block& blk, const PlanarState& s, double dt,
                        std::vector<ContactHistory>& hist) {
  PlanarLoad out;
  const double c = std::cos(s.theta), sn = std::sin(s.theta);
  const double face = blk.face_area();
  for (std::size_t i = 0; i < blk.r.size(); ++i) {
    // Rotation about +y: (x, z) -> (c x + s z, -s x + c z).
    const Vector3d rr(c * blk.r[i].x() + sn * blk.r[i].z(), blk.r[i].y(),
                      -sn * blk.r[i].x() + c * blk.r[i].z());
    const Vector3d omega(0, s.w, 0);
    ContactPoint p;
    p.normal = Vector3d::UnitZ();
    p.overlap = -(s.z + rr.z());
    p.velocity = Vector3d(s.vx, 0, s.vz) + omega.cross(rr);
    p.area = blk.areas[i];
    p.effective_mass = blk.mass * blk.areas[i] / face;
    const ContactForce f = law.compute(p, dt, hist[i]);
    out.fx += f.force.x();
    out.fz += f.force.z();
    out.torque += rr.z() * f.force.x() - rr.x() * f.force.z();
    out.sliding += f.sliding;
  }
  return out;
}

// Velocity Verlet for `steps` steps; returns the largest |theta| seen.
double run_block(const ContactLaw& law, const Block& blk, PlanarState& s,
                 std::vector<ContactHistory>& hist, double dt, long steps, double gravity) {
  const double Iy = blk.inertia()(1, 1);
  PlanarLoad load = block_forces(law, blk, s, dt, hist);
  double max_theta = std::abs(s.theta);
  for (long k = 0; k < steps; ++k) {
    s.vx += 0.5 * dt * load.fx / blk.mass;
    s.vz += 0.5 * dt * (load.fz / blk.mass - gravity);
    s.w += 0.5 * dt * load.torque / Iy;
    s.x += dt * s.vx;
    s.z += dt * s.vz;
    s.theta += dt * s.w;
    load = block_forces(law, blk, s, dt, hist);
    s.vx += 0.5 * dt * load.fx / blk.mass;
    s.vz += 0.5 * dt * (load.fz / blk.mass - gravity);
    s.w += 0.5 * dt * load.torque / Iy;
    max_theta = std::max(max_theta, std::abs(s.theta));
    if (!std::isfinite(s.theta) || max_theta > 1.0) return INFINITY;
  }
  return max_theta;
}

ContactBody body_at_rest(const Block& blk, double z) {
  ContactBody body;
  body.mass = blk.mass;
  body.inertia = blk.inertia();
  body.com = Vector3d(0, 0, z);
  return body;
}

std::vector<Vector3d> world_nodes(const Block& blk, double z) {
  std::vector<Vector3d> pts;
  for (const Vector3d& r : blk.r) pts.push_back(Vector3d(0, 0, z) + r);
  return pts;
}

}  // namespace

TEST(ContactResting, DroppedBlockSettlesToClosedFormOverlap) {
  // A granite block 0.6 x 0.6 x 0.8 m on 36 nodes, released tilted by 0.005
  // rad with one edge touching: it rocks, impacts, slides a little and comes
  // to rest. The static overlap must then be the closed form of the whole
  // face, M g / (k_a A) (linear) or delta_ref (M g / (k_a A delta_ref))^{2/3}
  // (Hertz), independent of the grid. After 2 s the motion has decayed to
  // round-off (speed ~1e-12 m/s, printed), so the tolerance is 1e-8 relative.
  for (NormalLaw kind : {NormalLaw::kLinear, NormalLaw::kHertz}) {
    ContactParams p = params(kind, 0.4);
    p.tangential_damping_ratio = 0.3;
    const ContactLaw law(p);
    const Block blk(0.3, 0.3, 0.4, 2700.0, 6);
    const double weight = blk.mass * kGravity;
    const double ka = 2e9, A = blk.face_area();
    const double expected = kind == NormalLaw::kLinear
                                ? weight / (ka * A)
                                : 1e-5 * std::pow(weight / (ka * A * 1e-5), 2.0 / 3.0);
    EXPECT_NEAR(law.overlap_under_load(A, weight), expected, 1e-14 * expected);

    PlanarState s;
    s.theta = 0.005;
    double lowest = 0;  // z of the lowest node relative to the COM
    for (const Vector3d& r : blk.r)
      lowest = std::min(lowest, -std::sin(s.theta) * r.x() + std::cos(s.theta) * r.z());
    s.z = -lowest;
    std::vector<ContactHistory> hist(blk.r.size());
    const double overlap_max = law.impact_overlap(A, blk.mass, 1.0);
    const freestand::ContactModes modes = freestand::resting_critical_time_step(
        law, world_nodes(blk, blk.h), blk.areas, Vector3d::UnitZ(), overlap_max,
        body_at_rest(blk, blk.h));
    const double dt = 0.05 * modes.time_step;
    const long steps = static_cast<long>(2.0 / dt);
    run_block(law, blk, s, hist, dt, steps, kGravity);
    const double overlap = blk.h - s.z;
    std::printf("[measured] %s block at rest after 2 s: overlap %.9e m (closed form %.9e), "
                "tilt %.1e rad, speed %.1e m/s\n",
                kind == NormalLaw::kLinear ? "linear" : "Hertz ", overlap, expected, s.theta,
                std::hypot(s.vx, s.vz));
    EXPECT_NEAR(overlap, expected, 1e-8 * expected);
    EXPECT_LT(std::abs(s.theta), 1e-8 * expected / blk.b);
  }
}

// ---------------------------------------------------------------------------
// Critical time step

TEST(ContactTimeStep, OscillatorFormula) {
  // 2/omega (sqrt(1 + zeta^2) - zeta).
  EXPECT_NEAR(freestand::oscillator_critical_time_step(4e6, 1.0, 0.0), 1e-3, 1e-15);
  EXPECT_NEAR(freestand::oscillator_critical_time_step(4e6, 1.0, 0.75), 1e-3 * 0.5, 1e-15);
  EXPECT_THROW(freestand::oscillator_critical_time_step(-1.0, 1.0, 0.0), freestand::InputError);
  EXPECT_THROW(freestand::oscillator_critical_time_step(1.0, 0.0, 0.0), freestand::InputError);
  // Per-area stiffness with the recommended m_eff: every node of a face has
  // the whole face's bounce frequency, whatever the node count.
  const ContactLaw law(params(NormalLaw::kLinear, 0.5));
  const double M = 800.0, face = 0.36;
  const double whole = freestand::face_critical_time_step(law, face, M, 0.0);
  for (int nodes : {4, 16, 64})
    EXPECT_NEAR(freestand::face_critical_time_step(law, face / nodes, M / nodes, 0.0), whole,
                1e-14 * whole);
}

TEST(ContactTimeStep, OscillatorLimitIsSharpUnderLiggghtsVerlet) {
  // A mass resting on one node under gravity, nudged by 1e-6 of its static
  // overlap: decays (or oscillates) at 0.98 of the limit, grows by > 1e4 at
  // 1.02 (it saturates at ~1e6, when the mass starts to bounce).
  const double m = 100.0, A = 0.05;
  for (double zeta : {0.0, 0.3, 1.5}) {
    ContactParams p = params(NormalLaw::kLinear, 1.0);
    p.restitution.reset();
    p.damping_ratio = zeta;
    const ContactLaw law(p);
    const double dt_crit = freestand::face_critical_time_step(law, A, m, 0.0);
    EXPECT_NEAR(dt_crit, freestand::oscillator_critical_time_step(2e9 * A, m, zeta), 1e-15);
    const double rest = m * kGravity / (2e9 * A);
    for (double fraction : {0.98, 1.02}) {
      const double dt = fraction * dt_crit;
      double z = -rest * (1.0 + 1e-6), v = 0.0;
      ContactHistory h;
      double f = law.compute(vertical_point(-z, v, A, m), dt, h).force.z();
      double worst = 0.0;
      for (int i = 0; i < 4000; ++i) {
        v += 0.5 * dt * (f / m - kGravity);
        z += dt * v;
        f = law.compute(vertical_point(-z, v, A, m), dt, h).force.z();
        v += 0.5 * dt * (f / m - kGravity);
        worst = std::max(worst, std::abs(z + rest));
      }
      const double growth = worst / (1e-6 * rest);
      std::printf("[measured] 1-dof zeta %.1f at %.2f dt_crit: largest deviation %.1e x initial\n",
                  zeta, fraction, growth);
      if (fraction < 1.0)
        EXPECT_LT(growth, 10.0) << "zeta " << zeta;
      else
        EXPECT_GT(growth, 1e4) << "zeta " << zeta;
    }
  }
}

TEST(ContactTimeStep, RestingBoxModesMatchClosedForm) {
  // Box on its base face (fixed table): the vertical bounce K/M, the twist
  // kappa k_a S / I_z and, in each vertical plane, the 2 x 2 rocking-sliding
  // problem with stiffness [[kK, -kK h], [-kK h, kK h^2 + k_a S_x]] and mass
  // diag(M, I_y), S_x = sum A_i x_i^2. The highest is rocking-sliding.
  ContactParams p = params(NormalLaw::kLinear, 1.0);
  const ContactLaw law(p);
  const double kappa = freestand::kDefaultTangentialStiffnessRatio, ka = 2e9;
  const Block blk(0.2, 0.3, 0.5, 2500.0, 5);
  const double K = ka * blk.face_area(), M = blk.mass;
  const Matrix3d I = blk.inertia();
  double Sx = 0, Sy = 0;
  for (std::size_t i = 0; i < blk.r.size(); ++i) {
    Sx += blk.areas[i] * blk.r[i].x() * blk.r[i].x();
    Sy += blk.areas[i] * blk.r[i].y() * blk.r[i].y();
  }
  auto rocking_sliding = [&](double S, double inertia) {
    const double a = M * inertia;
    const double bq = kappa * K * inertia + M * (kappa * K * blk.h * blk.h + ka * S);
    const double c = kappa * K * ka * S;
    return (bq + std::sqrt(bq * bq - 4 * a * c)) / (2 * a);
  };
  const double expected =
      std::max({K / M, kappa * ka * (Sx + Sy) / I(2, 2), rocking_sliding(Sx, I(1, 1)),
                rocking_sliding(Sy, I(0, 0))});
  const freestand::ContactModes modes = freestand::resting_critical_time_step(
      law, world_nodes(blk, blk.h), blk.areas, Vector3d::UnitZ(), 0.0, body_at_rest(blk, blk.h));
  EXPECT_NEAR(modes.omega_max * modes.omega_max, expected, 1e-10 * expected);
  EXPECT_NEAR(modes.time_step, 2.0 / std::sqrt(expected), 1e-9 * modes.time_step);
  std::printf("[measured] box 0.4 x 0.6 x 1.0 m on its base: omega_max / omega_bounce = %.3f\n",
              modes.omega_max / std::sqrt(K / M));
  EXPECT_GT(modes.omega_max, 1.5 * std::sqrt(K / M));

  // Against a second, very heavy body instead of the table: the same modes.
  ContactBody heavy = body_at_rest(blk, -blk.h);
  heavy.mass *= 1e9;
  heavy.inertia *= 1e9;
  const freestand::ContactModes two = freestand::resting_critical_time_step(
      law, world_nodes(blk, blk.h), blk.areas, Vector3d::UnitZ(), 0.0, body_at_rest(blk, blk.h),
      &heavy);
  EXPECT_NEAR(two.omega_max, modes.omega_max, 1e-6 * modes.omega_max);
  // Two equal blocks that cannot rotate (huge inertia): only the relative
  // translation is left, bouncing at K / m_red = 2 K / M.
  ContactBody upper = body_at_rest(blk, blk.h), lower = body_at_rest(blk, -blk.h);
  upper.inertia *= 1e12;
  lower.inertia *= 1e12;
  const freestand::ContactModes pair = freestand::resting_critical_time_step(
      law, world_nodes(blk, blk.h), blk.areas, Vector3d::UnitZ(), 0.0, upper, &lower);
  EXPECT_NEAR(pair.omega_max * pair.omega_max, 2 * K / M, 1e-6 * K / M);
}

TEST(ContactTimeStep, RestingBlockLimitIsSharp) {
  // The planar block on 16 nodes, undamped and stuck: its fastest mode is
  // rocking-sliding, ~1.7 times the bounce frequency. At 0.97 of
  // resting_critical_time_step the run stays bounded, at 1.03 it blows up,
  // while the bounce-mode estimate alone would allow a 1.7 times larger step.
  ContactParams p = params(NormalLaw::kLinear, 1.0);
  p.mu_s = p.mu_k = 10.0;
  const ContactLaw law(p);
  const Block blk(0.2, 0.2, 0.4, 2700.0, 4);
  const double rest = blk.mass * kGravity / (2e9 * blk.face_area());
  const freestand::ContactModes modes = freestand::resting_critical_time_step(
      law, world_nodes(blk, blk.h - rest), blk.areas, Vector3d::UnitZ(), rest,
      body_at_rest(blk, blk.h - rest));
  const double bounce = freestand::face_critical_time_step(law, blk.face_area(), blk.mass, rest);
  std::printf("[measured] 0.4 x 0.4 x 0.8 m block: resting limit %.3e s, bounce-mode %.3e s\n",
              modes.time_step, bounce);
  EXPECT_LT(modes.time_step, 0.7 * bounce);
  for (double fraction : {0.97, 1.03}) {
    PlanarState s;
    s.z = blk.h - rest;
    s.theta = 1e-7;
    std::vector<ContactHistory> hist(blk.r.size());
    const double worst = run_block(law, blk, s, hist, fraction * modes.time_step, 3000, kGravity);
    std::printf("[measured] block at %.2f of the resting limit: largest tilt %.1e x initial\n",
                fraction, worst / 1e-7);
    if (fraction < 1.0)
      EXPECT_LT(worst, 10 * 1e-7);
    else
      EXPECT_GT(worst, 1e3 * 1e-7);
  }
}

TEST(ContactTimeStep, SingleNodeImpactNeverStifferThanTheFace) {
  // A corner node hitting alone carries the body's point mass at that node
  // (smaller than M), but only its own small stiffness: its frequency is
  // below the whole face's highest one (adding springs only raises
  // frequencies). The Rayleigh bound max(1, kappa) K / min m_point caps both.
  const ContactLaw law(params(NormalLaw::kLinear, 1.0));
  const Block blk(0.2, 0.3, 0.5, 2500.0, 5);
  const ContactBody body = body_at_rest(blk, blk.h);
  const freestand::ContactModes modes = freestand::resting_critical_time_step(
      law, world_nodes(blk, blk.h), blk.areas, Vector3d::UnitZ(), 0.0, body);
  double min_point_mass = INFINITY, fastest_single = 0;
  for (std::size_t i = 0; i < blk.r.size(); ++i) {
    const double mp = freestand::smallest_point_mass(body, blk.r[i]);
    min_point_mass = std::min(min_point_mass, mp);
    const freestand::ContactModes single = freestand::resting_critical_time_step(
        law, {world_nodes(blk, blk.h)[i]}, {blk.areas[i]}, Vector3d::UnitZ(), 0.0, body);
    fastest_single = std::max(fastest_single, single.omega_max);
    EXPECT_LE(single.omega_max, modes.omega_max) << "node " << i;
    EXPECT_LE(single.omega_max * single.omega_max, 2e9 * blk.areas[i] / mp * (1 + 1e-12));
  }
  EXPECT_GT(min_point_mass, 0.0);
  EXPECT_LT(min_point_mass, blk.mass / 3);
  const double bound = 2e9 * blk.face_area() / min_point_mass;
  EXPECT_LE(modes.omega_max * modes.omega_max, bound);
  std::printf("[measured] fastest single node %.0f rad/s, face %.0f rad/s, Rayleigh bound %.0f rad/s\n",
              fastest_single, modes.omega_max, std::sqrt(bound));
}

TEST(ContactTimeStep, CheckSaysWhatToUse) {
  const ContactLaw linear(params(NormalLaw::kLinear, 0.5));
  const ContactLaw hertz(params(NormalLaw::kHertz, 0.5));
  EXPECT_NO_THROW(freestand::check_time_step(linear, 2e-5, 2e-5, "pair convex"));
  for (const ContactLaw* law : {&linear, &hertz}) {
    try {
      freestand::check_time_step(*law, 3e-5, 2e-5, "pair convex");
      ADD_FAILURE() << "no error";
    } catch (const freestand::InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("pair convex: timestep 3e-05 s is above the critical time step 2e-05 s"),
                std::string::npos) << m;
      const std::string use = law == &linear ? "use timestep 4e-07 or less (0.02 of"
                                             : "use timestep 2e-06 or less (0.1 of";
      EXPECT_NE(m.find(use), std::string::npos) << m;
    }
  }
  EXPECT_THROW(freestand::check_time_step(linear, 0.0, 2e-5, "x"), freestand::InputError);
}

// Cost of one compute() call (not a test: timing depends on the machine).
// build-cl/unit_tests --gtest_filter='*ContactLawBench*' --gtest_also_run_disabled_tests
TEST(DISABLED_ContactLawBench, CostPerCall) {
  for (NormalLaw kind : {NormalLaw::kLinear, NormalLaw::kHertz}) {
    ContactParams p = params(kind, 0.5);
    p.friction_decay = 2.0;
    const ContactLaw law(p);
    const int n = 1 << 20;
    std::vector<ContactHistory> hist(64);
    ContactPoint c;
    c.normal = Vector3d(0.1, 0.2, 1.0).normalized();
    c.area = 0.01;
    c.effective_mass = 10.0;
    double sink = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) {
      c.overlap = 1e-5 * (1.0 + 0.5 * ((i * 7) % 13) / 13.0);
      c.velocity = Vector3d(1e-3 * ((i % 5) - 2), 1e-4 * ((i % 3) - 1), -1e-3);
      sink += law.compute(c, 1e-6, hist[i & 63]).force.x();
    }
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / n;
    std::printf("[measured] %s compute(): %.1f ns per call (checksum %g)\n",
                kind == NormalLaw::kLinear ? "linear" : "Hertz", ns, sink);
  }
}
