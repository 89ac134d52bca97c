#include "winkler_rocking.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace freestand::reference {

namespace {

// Restitution of the clamped single-dof impact of damping ratio zeta (unit
// frequency, unit approach speed): RK4 on x'' = -x - 2 zeta x' from x = 0,
// x' = 1 until the force x + 2 zeta x' reaches 0; the exit speed is
// interpolated linearly at that crossing (error O(step^2) ~ 1e-8).
double single_dof_restitution(double zeta) {
  const double step = 1e-3 / (1.0 + 2.0 * zeta);  // resolves the dashpot time 1/(2 zeta)
  auto acceleration = [zeta](double x, double v) { return -x - 2.0 * zeta * v; };
  double x = 0.0, v = 1.0;
  for (;;) {
    const double k1x = v, k1v = acceleration(x, v);
    const double k2x = v + 0.5 * step * k1v, k2v = acceleration(x + 0.5 * step * k1x, v + 0.5 * step * k1v);
    const double k3x = v + 0.5 * step * k2v, k3v = acceleration(x + 0.5 * step * k2x, v + 0.5 * step * k2v);
    const double k4x = v + step * k3v, k4v = acceleration(x + step * k3x, v + step * k3v);
    const double xn = x + step / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double vn = v + step / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    const double force = x + 2.0 * zeta * v, force_next = xn + 2.0 * zeta * vn;
    if (force_next <= 0.0) {
      const double f = force / (force - force_next);
      return -(v + f * (vn - v));
    }
    x = xn;
    v = vn;
  }
}

// The horizontal motion does not enter the forces (flat base, no slip at
// the centre of pressure), so it is not integrated.
struct State {
  double z, vz, theta, omega;  // COM height and its rate, tilt and its rate
};

// Pressure resultant over the base: vertical force, its moment about the COM
// (rocking axis), and the centre of pressure s_c (body coordinate along the base).
struct Pressure {
  double force = 0.0, moment = 0.0, centre = 0.0;
};

// Clips [lo, hi] to where f0 + f1 s > 0.
void clip_positive(double f0, double f1, double& lo, double& hi) {
  if (f1 > 0.0) lo = std::max(lo, -f0 / f1);
  else if (f1 < 0.0) hi = std::min(hi, -f0 / f1);
  else if (f0 <= 0.0) hi = lo;  // empty
}

Pressure pressure(const WinklerBlock& b, const State& s) {
  const double c = std::cos(s.theta), sn = std::sin(s.theta), h = b.half_height;
  // delta(s) = a0 + a1 s; d(delta)/dt = d0 + d1 s; p = q0 + q1 s where both > 0.
  const double a0 = h * c - s.z, a1 = sn;
  const double d0 = -h * sn * s.omega - s.vz, d1 = c * s.omega;
  const double q0 = b.stiffness * a0 + b.damping * d0, q1 = b.stiffness * a1 + b.damping * d1;
  double lo = -b.half_width, hi = b.half_width;
  clip_positive(a0, a1, lo, hi);
  clip_positive(q0, q1, lo, hi);
  Pressure out;
  if (hi <= lo) return out;
  const double l1 = hi - lo, l2 = (hi * hi - lo * lo) / 2.0, l3 = (hi * hi * hi - lo * lo * lo) / 3.0;
  out.force = b.depth * (q0 * l1 + q1 * l2);
  const double first_moment = b.depth * (q0 * l2 + q1 * l3);  // integral of s p dA
  if (!(out.force > 0.0)) return Pressure{};
  out.centre = first_moment / out.force;
  // Lever r_x(s) = s cos(theta) - h sin(theta); a vertical force at r gives r_z F_x - r_x F_z.
  out.moment = -c * first_moment + h * sn * out.force;
  return out;
}

// Horizontal lever of the no-slip point: its depth below the COM, L(s_c).
double depth_below_com(const WinklerBlock& b, const State& s, double centre) {
  return centre * std::sin(s.theta) + b.half_height * std::cos(s.theta);
}

State derivative(const WinklerBlock& b, const State& s) {
  const Pressure p = pressure(b, s);
  if (!(p.force > 0.0)) return State{s.vz, -b.gravity, s.omega, 0.0};  // in flight
  // No slip at the centre of pressure s_c: the base point there has no
  // horizontal acceleration, x'' = theta'' L + omega^2 r_x(s_c) (s_c held:
  // L' = omega r_x), with m x'' = lambda (horizontal force at s_c) and
  // I theta'' = M - L lambda.
  const double lever = depth_below_com(b, s, p.centre);
  const double r_x = p.centre * std::cos(s.theta) - b.half_height * std::sin(s.theta);
  const double lambda = (lever * p.moment / b.inertia + s.omega * s.omega * r_x) /
                        (1.0 / b.mass + lever * lever / b.inertia);
  return State{s.vz, p.force / b.mass - b.gravity, s.omega, (p.moment - lever * lambda) / b.inertia};
}

State add(const State& s, const State& d, double f) {
  return State{s.z + f * d.z, s.vz + f * d.vz, s.theta + f * d.theta, s.omega + f * d.omega};
}

}  // namespace

double single_dof_damping_ratio(double restitution) {
  if (!(restitution > 0.0 && restitution < 1.0))
    throw std::invalid_argument("single_dof_damping_ratio: restitution must be in (0, 1)");
  double lo = 0.0, hi = 1.0;
  while (single_dof_restitution(hi) > restitution) {
    lo = hi;
    hi *= 2.0;
  }
  while (hi - lo > 1e-9 * hi) {
    const double mid = 0.5 * (lo + hi);
    (single_dof_restitution(mid) > restitution ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double winkler_damping(const WinklerBlock& block, double zeta) {
  const double area = 2.0 * block.half_width * block.depth;
  return 2.0 * zeta * std::sqrt(block.stiffness * block.mass / area);
}

std::vector<WinklerSample> winkler_rocking(const WinklerBlock& block, double theta0, double t_end,
                                           double dt, int every) {
  State s{block.half_width * std::sin(theta0) + block.half_height * std::cos(theta0), 0.0,
          theta0, 0.0};
  std::vector<WinklerSample> out{{0.0, s.theta, s.omega}};
  const long steps = std::lround(t_end / dt);
  for (long n = 1; n <= steps; ++n) {
    const State k1 = derivative(block, s);
    const State k2 = derivative(block, add(s, k1, 0.5 * dt));
    const State k3 = derivative(block, add(s, k2, 0.5 * dt));
    const State k4 = derivative(block, add(s, k3, dt));
    s = add(s, k1, dt / 6.0);
    s = add(s, k2, dt / 3.0);
    s = add(s, k3, dt / 3.0);
    s = add(s, k4, dt / 6.0);
    if (n % every == 0) out.push_back({n * dt, s.theta, s.omega});
  }
  return out;
}

}  // namespace freestand::reference
