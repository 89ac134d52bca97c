// Energy ledger of the contact law (docs/fix_rigid_convex.md, "Energy ledger"):
// the dissipation ContactLaw::compute() reports per step is measured from the
// forces and velocities of that step, not as a remainder; these tests close
// the balance kinetic + elastic + dissipated = initial (+ work of the table)
// on single-dof dynamics integrated as LIGGGHTS does (velocity Verlet, the
// law evaluated with the half-step velocity).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "freestand/contact_law.h"

namespace {

using freestand::ContactForce;
using freestand::ContactHistory;
using freestand::ContactLaw;
using freestand::ContactParams;
using freestand::ContactPoint;
using freestand::NormalLaw;

constexpr double kPi = 3.14159265358979323846;

ContactParams params(NormalLaw law, double e) {
  ContactParams p;
  p.law = law;
  p.stiffness_per_area = 1e6;
  p.hertz_reference_overlap = 1e-3;
  p.restitution = e;
  p.mu_s = p.mu_k = 0.5;
  return p;
}

struct ImpactLedger {
  double initial = 0, final_kinetic = 0, normal = 0, friction = 0, worst_balance = 0, elastic_peak = 0;
};

// A 1 kg mass (area 1 m^2) hits the plane face-on at 1 m/s, no gravity.
ImpactLedger impact(NormalLaw law, double e, double dt) {
  const ContactLaw contact(params(law, e));
  const double m = 1.0;
  double z = 0.0, v = -1.0, f = 0.0;
  ContactHistory history;
  ImpactLedger out;
  out.initial = 0.5 * m * v * v;
  for (long step = 0; step < 10000000; ++step) {
    const double half = v + 0.5 * dt * f / m;
    z += half * dt;
    const ContactPoint point{Eigen::Vector3d::UnitZ(), -z, Eigen::Vector3d(0, 0, half), 1.0, m};
    const ContactForce r = contact.compute(point, dt, history);
    f = r.force.z();
    v = half + 0.5 * dt * f / m;
    out.normal += r.normal_dissipation;
    out.friction += r.friction_dissipation;
    out.elastic_peak = std::max(out.elastic_peak, r.elastic_energy());
    const double balance = 0.5 * m * v * v + r.elastic_energy() + out.normal - out.initial;
    out.worst_balance = std::max(out.worst_balance, std::fabs(balance));
    if (z > 0.0 && v > 0.0) break;
  }
  out.final_kinetic = 0.5 * m * v * v;
  return out;
}

TEST(ContactEnergy, ImpactDissipationIsTheLostKineticEnergy) {
  for (NormalLaw law : {NormalLaw::kLinear, NormalLaw::kHertz}) {
    for (double e : {0.9, 0.5, 0.1}) {
      const ImpactLedger l = impact(law, e, 1e-6);
      const double lost = l.initial - l.final_kinetic;
      std::printf("[validation] contact energy, %s impact e = %.1f: KE lost %.6f J, dashpot %.6f J "
                  "(%.2e relative), worst running balance %.2e J, peak elastic %.4f J\n",
                  law == NormalLaw::kLinear ? "linear" : "Hertz", e, lost, l.normal,
                  (l.normal - lost) / lost, l.worst_balance, l.elastic_peak);
      // The dashpot force jumps on at first touch: an O(dt) error of the
      // discrete accounting (c v^2 dt / 2), 1.2e-3 of the loss for e = 0.1.
      EXPECT_NEAR(l.normal, lost, 3e-3 * lost);
      EXPECT_NEAR(lost, l.initial * (1 - e * e), 2e-3 * l.initial);  // the restitution asked for
      EXPECT_LT(l.worst_balance, 3e-3 * l.initial);  // at every step, to the integration error
      EXPECT_EQ(l.friction, 0.0);                    // face-on: nothing tangential
      EXPECT_GT(l.elastic_peak, 0.05 * l.initial * e);
    }
  }
}

TEST(ContactEnergy, ImpactLedgerConvergesWithTheTimeStep) {
  const ImpactLedger coarse = impact(NormalLaw::kLinear, 0.5, 4e-5), fine = impact(NormalLaw::kLinear, 0.5, 1e-5);
  const double err_coarse = std::fabs(coarse.normal - (coarse.initial - coarse.final_kinetic));
  const double err_fine = std::fabs(fine.normal - (fine.initial - fine.final_kinetic));
  EXPECT_LT(err_fine, 0.5 * err_coarse + 1e-12);
}

TEST(ContactEnergy, ElasticEnergyIsTheIntegralOfTheElasticForce) {
  for (NormalLaw law : {NormalLaw::kLinear, NormalLaw::kHertz}) {
    const ContactLaw contact(params(law, 0.5));
    const double delta = 2e-3, area = 0.3;
    double integral = 0.0;
    const int n = 100000;
    for (int k = 0; k < n; ++k) integral += contact.elastic_force(area, (k + 0.5) * delta / n) * delta / n;
    EXPECT_NEAR(contact.elastic_energy(area, delta), integral, 1e-8 * integral);
    ContactHistory history;
    const ContactForce r = contact.compute(
        {Eigen::Vector3d::UnitZ(), delta, Eigen::Vector3d::Zero(), area, 1.0}, 1e-6, history);
    EXPECT_NEAR(r.normal_energy, integral, 1e-8 * integral);
    EXPECT_EQ(contact.elastic_energy(area, -1e-3), 0.0);
  }
}

// A 1 kg block at a constant overlap (F_n = 10 N, mu_s 0.5, mu_k 0.4,
// tangential dashpot zeta_t 0.3) on a table moving x = -(W / w) cos(w t):
// it sticks near the velocity peaks and slips near the acceleration peaks.
// Kinetic + tangential elastic + dissipated - initial = table work
// sum F_t . v_table dt.
TEST(ContactEnergy, StickSlipCycleBalancesTheTableWork) {
  ContactParams p = params(NormalLaw::kLinear, 0.5);
  p.mu_s = 0.5;
  p.mu_k = 0.4;
  p.tangential_damping_ratio = 0.3;
  const ContactLaw contact(p);
  const double m = 1.0, delta = 1e-5, dt = 1e-5, W = 0.45, omega = 2 * kPi * 2.0;
  double u = 0.0, f = 0.0, dissipated = 0.0, work = 0.0, elastic = 0.0, steady = 0.0, steady_law = 0.0;
  long slips = 0, sticks = 0;
  ContactHistory history;
  const double initial = 0.0;
  bool was_sliding = false;
  for (long step = 1; step <= 200000; ++step) {
    const double t = step * dt, w = W * std::sin(omega * t);
    const double half = u + 0.5 * dt * f / m;
    const ContactPoint point{Eigen::Vector3d::UnitZ(), delta, Eigen::Vector3d(half - w, 0, 0), 1.0, m};
    const ContactForce r = contact.compute(point, dt, history);
    f = r.force.x();
    u = half + 0.5 * dt * f / m;
    dissipated += r.friction_dissipation + r.normal_dissipation;
    work += r.force.x() * w * dt;
    elastic = r.tangential_energy;
    if (r.sliding) {
      ++slips;
      // Steady sliding: the step dissipates mu_k F_n |v_t| dt.
      if (was_sliding) {
        steady += r.friction_dissipation;
        steady_law += p.mu_k * r.normal * std::fabs(half - w) * dt;
      }
    } else {
      ++sticks;
    }
    was_sliding = r.sliding;
  }
  const double total = 0.5 * m * u * u + elastic + dissipated - initial;
  std::printf("[validation] contact energy, stick-slip on a sine table (2 s, %ld slipping and %ld "
              "stuck steps): dissipated %.6f J, table work %.6f J, balance %.2e J (%.2e of the "
              "dissipated)\n",
              slips, sticks, dissipated, work, total - work, (total - work) / dissipated);
  EXPECT_GT(slips, 10000);
  EXPECT_GT(sticks, 10000);
  EXPECT_GT(dissipated, 0.1);
  EXPECT_NEAR(total, work, 1e-3 * dissipated);
  EXPECT_NEAR(steady, steady_law, 2e-3 * steady_law);
}

}  // namespace
