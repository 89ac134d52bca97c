#include "housner_pulse.h"

#include <algorithm>
#include <cmath>

namespace freestand::reference {

namespace {

struct State {
  double phi, omega;
};

State rk4(const HousnerBlock& block, const State& s, double a_over_g, double h) {
  const double alpha = block.alpha(), p2 = block.p() * block.p();
  auto f = [&](const State& x) {
    return State{x.omega, p2 * (a_over_g * std::cos(alpha - x.phi) - std::sin(alpha - x.phi))};
  };
  const State k1 = f(s);
  const State k2 = f({s.phi + 0.5 * h * k1.phi, s.omega + 0.5 * h * k1.omega});
  const State k3 = f({s.phi + 0.5 * h * k2.phi, s.omega + 0.5 * h * k2.omega});
  const State k4 = f({s.phi + h * k3.phi, s.omega + h * k3.omega});
  return {s.phi + h / 6 * (k1.phi + 2 * k2.phi + 2 * k3.phi + k4.phi),
          s.omega + h / 6 * (k1.omega + 2 * k2.omega + 2 * k3.omega + k4.omega)};
}

}  // namespace

bool overturns_rectangle_pulse(const HousnerBlock& block, double A, double td, double dt) {
  const double alpha = block.alpha(), a_over_g = A / block.gravity;
  if (a_over_g <= std::tan(alpha)) return false;
  State s{0.0, 0.0};
  // During the pulse: steps landing exactly on t_d.
  const long n = std::max(1L, static_cast<long>(std::ceil(td / dt)));
  const double h = td / n;
  for (long i = 0; i < n; ++i) {
    s = rk4(block, s, a_over_g, h);
    if (s.phi >= alpha) return true;  // both torques push outward from here on
  }
  // Free, conservative motion: overturn iff the energy carries phi past alpha.
  // Exact test: 0.5 omega^2 >= p^2 [cos(alpha - phi) - 1] (energy to the top).
  const double p2 = block.p() * block.p();
  if (s.omega > 0.0) return 0.5 * s.omega * s.omega >= p2 * (1.0 - std::cos(alpha - s.phi));
  return false;  // moving back toward phi = 0 with the base at rest
}

double rectangle_pulse_threshold(const HousnerBlock& block, double td, double rtol, double dt) {
  double lo = block.gravity * std::tan(block.alpha()), hi = 2.0 * lo;
  while (!overturns_rectangle_pulse(block, hi, td, dt)) hi *= 2.0;
  while (hi - lo > rtol * hi) {
    const double mid = 0.5 * (lo + hi);
    (overturns_rectangle_pulse(block, mid, td, dt) ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

double velocity_step_threshold(const HousnerBlock& block) {
  const double a = block.alpha();
  return std::sqrt(8.0 * block.gravity * block.R() * (1.0 - std::cos(a)) / 3.0) / std::cos(a);
}

double shenton_mu_required(double lambda, double beta) {
  return (lambda * (1.0 + 4.0 * beta * beta) + 3.0 * beta) /
         ((4.0 + beta * beta) + 3.0 * lambda * beta);
}

InitialMode shenton_initial_mode(double b, double h, double mu, double lambda, double g) {
  const double beta = b / h, R2 = b * b + h * h;
  const bool slides = lambda > mu && mu < beta;
  if (lambda <= beta && !slides) return {0, 0.0, 0.0};
  if (mu < beta) return {1, 0.0, -(lambda - mu) * g};
  if (mu >= shenton_mu_required(lambda, beta))
    return {2, 3.0 * g * (lambda * h - b) / (4.0 * R2), 0.0};
  const double q = h * mu - b;
  const double theta_dd = 3.0 * g * q / (R2 - 3.0 * b * q);
  return {3, theta_dd, -lambda * g + mu * (g + theta_dd * b) + theta_dd * h};
}

}  // namespace freestand::reference
