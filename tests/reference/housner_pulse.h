#ifndef FREESTAND_TESTS_HOUSNER_PULSE_H
#define FREESTAND_TESTS_HOUSNER_PULSE_H

// Independent reference for the overturning of a rigid rectangular block
// resting on a base that receives a rectangular acceleration pulse
// (../shared/data/benchmarks.md 1.6-1.7), used only by tests. Written from
// Housner's nonlinear equation of motion (benchmarks.md 1.1), sharing no
// code with freestand: phi >= 0 is the tilt away from the pulse, about the
// trailing corner,
//   phi'' = p^2 [ (a(t)/g) cos(alpha - phi) - sin(alpha - phi) ],
// a(t) = A for 0 <= t < t_d, then 0 (the base keeps its velocity).
// After the pulse the motion is conservative until the impact at phi = 0,
// after which the block (having less energy, no excitation) can never
// overturn; so the block overturns iff phi reaches alpha.

#include "housner.h"

namespace freestand::reference {

// Integrates the equation above by RK4 with step dt (landing exactly on
// t_d); true iff phi reaches alpha before returning to 0. A <= g tan(alpha)
// does not uplift: false.
bool overturns_rectangle_pulse(const HousnerBlock& block, double A, double td, double dt = 1e-5);

// The smallest overturning amplitude A (m/s^2) for pulse length t_d, by
// bisection on overturns_rectangle_pulse to a relative width rtol.
double rectangle_pulse_threshold(const HousnerBlock& block, double td, double rtol = 1e-7,
                                 double dt = 1e-5);

// Sudden base-velocity step (t_d -> 0, benchmarks.md 1.7), exact nonlinear:
// V_c = sqrt(8 g R (1 - cos alpha) / 3) / cos alpha.
double velocity_step_threshold(const HousnerBlock& block);

// Shenton (1996) / benchmarks.md 2.1: friction needed for pure rocking at the
// instant of uplift under a table acceleration lambda g, beta = b / h:
// mu_req = [lambda (1 + 4 beta^2) + 3 beta] / [(4 + beta^2) + 3 lambda beta].
double shenton_mu_required(double lambda, double beta);

// Initial accelerations (from rest, at the instant the table acceleration
// lambda g is applied) of a rigid rectangle with half sizes b, h and Coulomb
// friction mu, in the table's frame, tilting away from the acceleration about
// its trailing corner: the regime (0 rest, 1 slide, 2 rock, 3 slide-rock),
// the angular acceleration (rad/s^2) and the slip acceleration of the pivot
// corner (m/s^2, <= 0: against the table's acceleration). Derived from the
// Newton-Euler equations (I_c = m R^2 / 3); slide-rock: friction mu N at the
// sliding pivot, theta'' = 3 g (h mu - b) / (R^2 - 3 b (h mu - b)).
struct InitialMode {
  int regime;
  double theta_dd;
  double slip_dd;
};
InitialMode shenton_initial_mode(double b, double h, double mu, double lambda, double g = 9.81);

}  // namespace freestand::reference

#endif
