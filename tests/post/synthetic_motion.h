#ifndef FREESTAND_TESTS_POST_SYNTHETIC_MOTION_H
#define FREESTAND_TESTS_POST_SYNTHETIC_MOTION_H

// Synthetic free rocking of a rigid rectangular block for the analysis tests:
// the nonlinear rocking equation theta'' = -p^2 sin(alpha sgn(theta) - theta)
// between impacts, integrated with RK4 at a step far below the sampling step,
// and at each impact (theta = 0, located by bisection) theta' -> r theta'.
// Shares nothing with the code under test.

#include <cmath>
#include <utility>
#include <vector>

namespace freestand::test {

struct SyntheticRocking {
  std::vector<double> t, theta;  // samples (s, rad)
  std::vector<double> impact_times;       // exact (to the bisection tolerance), s
  std::vector<double> impact_velocities;  // |theta'| just before each impact, rad/s
};

inline SyntheticRocking free_rocking(double p, double alpha, double r, double theta0, double sample_step,
                                     double duration) {
  struct State {
    double theta, omega;
  };
  int side = theta0 > 0 ? 1 : -1;
  auto rhs = [&](const State& s) { return State{s.omega, -p * p * std::sin(alpha * side - s.theta)}; };
  auto rk4 = [&](const State& s, double h) {
    const State k1 = rhs(s), k2 = rhs({s.theta + 0.5 * h * k1.theta, s.omega + 0.5 * h * k1.omega});
    const State k3 = rhs({s.theta + 0.5 * h * k2.theta, s.omega + 0.5 * h * k2.omega});
    const State k4 = rhs({s.theta + h * k3.theta, s.omega + h * k3.omega});
    return State{s.theta + h / 6 * (k1.theta + 2 * k2.theta + 2 * k3.theta + k4.theta),
                 s.omega + h / 6 * (k1.omega + 2 * k2.omega + 2 * k3.omega + k4.omega)};
  };
  SyntheticRocking out;
  State state{theta0, 0.0};
  const int substeps = 200;  // RK4 local error (p h)^5 / 120 ~ 1e-18 rad at p ~ 4, h = 25 us
  const double h = sample_step / substeps;
  double time = 0;
  for (long k = 0; k * sample_step <= duration; ++k) {
    out.t.push_back(k * sample_step);
    out.theta.push_back(state.theta);
    for (int j = 0; j < substeps; ++j) {
      State next = rk4(state, h);
      if (next.theta * side < 0) {  // impact inside this substep: bisect for the crossing
        double lo = 0, hi = h;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          (rk4(state, mid).theta * side > 0 ? lo : hi) = mid;
        }
        state = rk4(state, hi);
        out.impact_times.push_back(time + hi);
        out.impact_velocities.push_back(std::fabs(state.omega));
        state = {0.0, r * state.omega};
        side = -side;
        next = rk4(state, h - hi);
      }
      state = next;
      time += h;
    }
    time = (k + 1) * sample_step;  // no drift of the sample clock
  }
  return out;
}

}  // namespace freestand::test

#endif
