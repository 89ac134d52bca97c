#ifndef FREESTAND_TESTS_WINKLER_ROCKING_H
#define FREESTAND_TESTS_WINKLER_ROCKING_H

// Independent reference for the rocking of a rigid block on a tensionless
// Winkler foundation (docs/validation.md, "Convex bodies: distributed base"):
// the continuum limit of fix rigid/convex's base grid, written from the
// equations, sharing no code with freestand.
//
// Planar (x, z, theta) block of base width 2b (in the rocking plane), depth D
// (normal to it), centre of mass at height h above the base centre. Under
// every base point s in [-b, b] a spring k_a and a dashpot c_a per unit area
// push with the pressure
//   p(s) = max(0, k_a delta(s) + c_a d(delta)/dt)   where delta(s) > 0, else 0,
//   delta(s) = s sin(theta) + h cos(theta) - z      (z: height of the COM),
// the per-node law of contact_law.h with the node's area shrunk to zero. p is
// linear in s on the interval where both conditions hold, so the resultant
// and its moment are integrated in closed form. Tangentially the base is
// rigid and does not slip: while any pressure acts, the base point under the
// centre of pressure has no horizontal acceleration (a pivot that moves along
// the base with the pressure; the horizontal motion then does not enter the
// forces and is not integrated). Fixed-step RK4.

#include <vector>

namespace freestand::reference {

struct WinklerBlock {
  double half_width;    // b (m), in the rocking plane
  double depth;         // D (m), normal to it
  double half_height;   // h (m): COM above the base centre
  double mass;          // m (kg)
  double inertia;       // about the COM, rocking axis (kg m^2)
  double stiffness;     // k_a (N/m^3)
  double damping;       // c_a (N s/m^3)
  double gravity = 9.81;
};

// c_a of fix rigid/convex's law: the dashpot 2 zeta sqrt(k_a A_k m A_k / A)
// of a node of area A_k is c_a A_k with c_a = 2 zeta sqrt(k_a m / A), A the
// base area, zeta the damping ratio whose clamped single-dof impact has
// restitution e (single_dof_damping_ratio).
double winkler_damping(const WinklerBlock& block, double zeta);

// Damping ratio zeta of a linear spring-dashpot whose impact, with the force
// clamped at zero (contact ends when k x + c x' reaches 0), has restitution e
// in (0, 1). Found by integrating that impact numerically and bisecting on
// zeta: independent of the closed form in contact_law.cpp. Accuracy ~1e-7.
double single_dof_damping_ratio(double restitution);

struct WinklerSample {
  double t, theta, omega;  // s, rad (positive leaning toward +x), rad/s
};

// Released at rest at tilt theta0 > 0 about the +x edge, that edge just
// touching (zero overlap); integrated to t_end with step dt, sampled every
// `every` steps (the first sample at t = 0).
std::vector<WinklerSample> winkler_rocking(const WinklerBlock& block, double theta0, double t_end,
                                           double dt, int every);

}  // namespace freestand::reference

#endif
