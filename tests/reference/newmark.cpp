#include "newmark.h"

#include <cmath>

namespace freestand::reference {

SlidingHistory newmark_sliding(const std::function<double(double)>& ag, double mu_s,
                               double mu_k, double g, double t_end, double sample, double dt) {
  SlidingHistory out;
  double u = 0.0, v = 0.0;  // relative displacement and velocity
  bool slipping = false;
  double next_sample = 0.0;
  const long steps = static_cast<long>(std::ceil(t_end / dt));
  for (long i = 0; i <= steps; ++i) {
    const double t = i * dt;
    if (t >= next_sample - 1e-12) {
      out.t.push_back(t);
      out.u.push_back(u);
      next_sample += sample;
    }
    const double a0 = ag(t), a1 = ag(t + dt);
    if (!slipping) {
      if (std::fabs(a0) <= mu_s * g) continue;
      slipping = true;  // the base pulls away: the block slides opposite to a_g
    }
    // Slip direction: current velocity, or at onset the sign opposite to a_g.
    const double dir = v != 0.0 ? (v > 0 ? 1.0 : -1.0) : (a0 > 0 ? -1.0 : 1.0);
    // Trapezoidal rule in the base acceleration (linear within the step).
    const double dv = -0.5 * (a0 + a1) * dt - mu_k * g * dir * dt;
    const double v_new = v + dv;
    if (v_new * dir < 0.0) {
      // Relative velocity reaches zero inside the step: stop there.
      const double f = v / (v - v_new);
      u += 0.5 * v * f * dt;
      v = 0.0;
      slipping = false;
    } else {
      u += 0.5 * (v + v_new) * dt;
      v = v_new;
    }
  }
  return out;
}

}  // namespace freestand::reference
