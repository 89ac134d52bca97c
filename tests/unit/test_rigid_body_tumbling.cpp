// Free tumbling of asymmetric rigid bodies: the intermediate-axis
// (Dzhanibekov) flip against the closed-form period, conservation of energy
// and angular momentum over long runs, second-order convergence against an
// independent RK4 integration of Euler's equations, and the accuracy of the
// chosen free-rotor splitting against NO_SQUISH. Numbers quoted in
// docs/rigid-body-integration.md are printed as "[ measured ]" lines by
//   build-rb/unit_tests --gtest_filter='RigidBody*'

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "freestand/rigid_body.h"

namespace freestand {
namespace {

using Eigen::AngleAxisd;
using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// The test body: principal moments 1, 2, 3 kg m^2, either given diagonal or
// as the full tensor Q diag(1, 2, 3) Q^T (principal axes = columns of Q).
const Vector3d kMoments(1.0, 2.0, 3.0);

Quaterniond tilt() {
  return Quaterniond(AngleAxisd(0.7, Vector3d(1.0, -2.0, 0.5).normalized())) *
         Quaterniond(AngleAxisd(-1.1, Vector3d(0.3, 0.4, -1.0).normalized()));
}

struct Body {
  Quaterniond Q;  // principal frame -> body frame
  Matrix3d inertia;  // body frame
  PreparedMassProperties props;
  explicit Body(const Quaterniond& q)
      : Q(q),
        inertia(q.toRotationMatrix() * kMoments.asDiagonal() * q.toRotationMatrix().transpose()),
        props(MassAndInertia{1.0, inertia}) {}
};

// Initial condition: spinning at 1 rad/s about the intermediate axis with a
// small perturbation, principal-frame angular velocity (0.005, 1, 0.01), the
// principal frame at kQ0 in the world whatever the body frame.
const Vector3d kOmegaPrincipal0(0.005, 1.0, 0.01);
const Quaterniond kQ0(AngleAxisd(0.9, Vector3d(1.0, 2.0, 3.0).normalized()));  // principal -> world

RigidBodyState start_state(const Body& b) {
  RigidBodyState s;
  s.orientation = kQ0 * b.Q.conjugate();  // body -> world
  s.angular_momentum = kQ0 * kMoments.cwiseProduct(kOmegaPrincipal0);
  return s;
}

// Principal-frame angular velocity of the state.
Vector3d principal_omega(const RigidBodyState& s, const Body& b) {
  return b.Q.conjugate() * body_angular_velocity(s, b.props);
}

// ---------------------------------------------------------------------------
// Closed form: Landau & Lifshitz, Mechanics, sec. 37. For L^2 > 2 E I2 the
// principal angular velocity is (cn, sn, dn)(tau) with
// tau = t sqrt((I3 - I2)(L^2 - 2 E I1) / (I1 I2 I3)) and modulus
// k^2 = (I2 - I1)(2 E I3 - L^2) / ((I3 - I2)(L^2 - 2 E I1)); for L^2 < 2 E I2
// swap I1 and I3. omega2 ~ sn changes sign every 2 K(k) in tau.

// Arithmetic-geometric mean; converges quadratically, so 8 iterations reach
// round-off for b/a >= 1e-3 (here b/a ~ 0.02).
double agm(double a, double b) {
  for (int i = 0; i < 8; ++i) {
    const double m = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = m;
  }
  return a;
}

// Time between successive sign changes of omega2 (s). The complementary
// modulus k'^2 = (I3 - I1)(L^2 - 2 E I2) / ((I3 - I2)(L^2 - 2 E I1)) is formed
// without cancellation: near the separatrix k is within 1e-4 of 1.
double analytic_flip_interval(const Vector3d& I, const Vector3d& w) {
  const double L2_minus_2EI1 = I(1) * (I(1) - I(0)) * w(1) * w(1) + I(2) * (I(2) - I(0)) * w(2) * w(2);
  const double L2_minus_2EI2 = I(0) * (I(0) - I(1)) * w(0) * w(0) + I(2) * (I(2) - I(1)) * w(2) * w(2);
  const double L2_minus_2EI3 = I(0) * (I(0) - I(2)) * w(0) * w(0) + I(1) * (I(1) - I(2)) * w(1) * w(1);
  const double I123 = I(0) * I(1) * I(2);
  double rate, kc2;
  if (L2_minus_2EI2 > 0) {
    rate = std::sqrt((I(2) - I(1)) * L2_minus_2EI1 / I123);
    kc2 = (I(2) - I(0)) * L2_minus_2EI2 / ((I(2) - I(1)) * L2_minus_2EI1);
  } else {
    rate = std::sqrt((I(1) - I(0)) * -L2_minus_2EI3 / I123);
    kc2 = (I(2) - I(0)) * -L2_minus_2EI2 / ((I(1) - I(0)) * -L2_minus_2EI3);
  }
  const double K = kPi / (2.0 * agm(1.0, std::sqrt(kc2)));
  return 2.0 * K / rate;
}

// Times at which x(t) changes sign, from linear interpolation between steps.
struct CrossingRecorder {
  double prev_t = 0.0, prev_x = 0.0;
  bool have_prev = false;
  std::vector<double> crossings;
  double min_x = 1e300, max_x = -1e300;
  void add(double t, double x) {
    if (have_prev && ((prev_x < 0) != (x < 0))) {
      crossings.push_back(prev_t + (t - prev_t) * prev_x / (prev_x - x));
    }
    prev_t = t;
    prev_x = x;
    have_prev = true;
    min_x = std::min(min_x, x);
    max_x = std::max(max_x, x);
  }
  // Largest relative deviation of successive crossing intervals from T.
  double worst_interval_error(double T) const {
    double worst = 0.0;
    for (size_t i = 1; i < crossings.size(); ++i) {
      worst = std::max(worst, std::fabs(crossings[i] - crossings[i - 1] - T) / T);
    }
    return worst;
  }
};

// ---------------------------------------------------------------------------
// Independent reference: classical RK4 on Euler's equations in the body frame
// with the full tensor (no eigen-decomposition):
//   dLb/dt = Lb x (I^-1 Lb),   dq/dt = q (0, I^-1 Lb) / 2.
struct Reference {
  Matrix3d inverse_inertia;
  Quaterniond q;
  Vector3d Lb;

  void derivative(const Quaterniond& qq, const Vector3d& L, Eigen::Vector4d& dq,
                  Vector3d& dL) const {
    const Vector3d w = inverse_inertia * L;
    dL = L.cross(w);
    dq = 0.5 * (qq * Quaterniond(0.0, w.x(), w.y(), w.z())).coeffs();
  }
  void step(double h) {
    Eigen::Vector4d k1q, k2q, k3q, k4q;
    Vector3d k1l, k2l, k3l, k4l;
    auto at = [&](const Eigen::Vector4d& dq, double f) {
      Quaterniond r;
      r.coeffs() = q.coeffs() + f * dq;
      return r;
    };
    derivative(q, Lb, k1q, k1l);
    derivative(at(k1q, h / 2), Lb + h / 2 * k1l, k2q, k2l);
    derivative(at(k2q, h / 2), Lb + h / 2 * k2l, k3q, k3l);
    derivative(at(k3q, h), Lb + h * k3l, k4q, k4l);
    q.coeffs() += h / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    q.normalize();
    Lb += h / 6 * (k1l + 2 * k2l + 2 * k3l + k4l);
  }
};

Reference reference_start(const Body& b) {
  const RigidBodyState s = start_state(b);
  return {b.inertia.inverse(), s.orientation, s.orientation.conjugate() * s.angular_momentum};
}

// Runs the integrator with zero force and torque.
template <class Observer>
void tumble(RigidBodyState& s, const PreparedMassProperties& p, double dt, long n,
            Observer&& observe) {
  for (long i = 1; i <= n; ++i) {
    initial_integrate(s, p, Vector3d::Zero(), Vector3d::Zero(), dt);
    final_integrate(s, p, Vector3d::Zero(), Vector3d::Zero(), dt);
    observe(i * dt, s);
  }
}

class RigidBodyTumbling : public ::testing::TestWithParam<bool> {
 protected:
  // Parameter: full (rotated) tensor or diagonal tensor.
  Body body{GetParam() ? tilt() : Quaterniond::Identity()};
};

INSTANTIATE_TEST_SUITE_P(RigidBodyTensor, RigidBodyTumbling, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Full" : "Diagonal"; });

TEST_P(RigidBodyTumbling, ReferenceReproducesEllipticFlipInterval) {
  // Validates the reference and the closed form against each other.
  Reference ref = reference_start(body);
  const double T = analytic_flip_interval(kMoments, kOmegaPrincipal0);
  CrossingRecorder w2;
  const double h = 1e-4;
  for (long i = 1; i <= 1000000; ++i) {  // 100 s
    ref.step(h);
    w2.add(i * h, (body.Q.conjugate() * (ref.inverse_inertia * ref.Lb))(1));
  }
  ASSERT_GE(w2.crossings.size(), 5u);
  const double err = w2.worst_interval_error(T);
  std::printf("[ measured ] RK4 h=1e-4: flip interval %.9f s, analytic %.9f s, rel. error %.2e\n",
              w2.crossings[2] - w2.crossings[1], T, err);
  // RK4 at h = 1e-4 and the linear interpolation of the crossings (omega2 is
  // odd about a crossing, so the O(h^2) term vanishes) leave ~1e-11 (measured
  // 7e-12 and 2e-11). A wrong modulus or rate is off by > 1e-2.
  EXPECT_LT(err, 1e-10);
}

TEST_P(RigidBodyTumbling, IntermediateAxisFlipsWithEllipticPeriod) {
  RigidBodyState s = start_state(body);
  const double T = analytic_flip_interval(kMoments, kOmegaPrincipal0);
  CrossingRecorder w2;
  tumble(s, body.props, 1e-3, 100000, [&](double t, const RigidBodyState& st) {
    w2.add(t, principal_omega(st, body)(1));
  });
  // 100 s hold five half-periods (T = 19.0 s): the body flips at least 4 times...
  ASSERT_GE(w2.crossings.size(), 4u);
  // ...and each flip is a full reversal of the spin, not a wobble.
  EXPECT_LT(w2.min_x, -0.99);
  EXPECT_GT(w2.max_x, 0.99);
  const double err = w2.worst_interval_error(T);
  std::printf("[ measured ] dt=1e-3 %s tensor: %zu flips, interval %.6f s vs analytic %.6f s, "
              "worst rel. error %.2e\n",
              GetParam() ? "full" : "diagonal", w2.crossings.size(),
              w2.crossings[1] - w2.crossings[0], T, err);
  // The O(dt^2) error of the orbit shifts the period: measured 1.6e-8 at
  // dt = 1e-3 (omega dt = 1e-3). The bound 1e-7 is met with a 6x margin; the
  // same scheme at 3x the step, or any first-order error, exceeds it.
  EXPECT_LT(err, 1e-7);
}

TEST_P(RigidBodyTumbling, EnergyBoundedAndAngularMomentumConserved) {
  RigidBodyState s = start_state(body);
  const Vector3d L0 = s.angular_momentum;
  const double E0 = kinetic_energy(s, body.props);
  const long n = 1000000;  // dt = 1e-3: 1000 s, ~52 flips
  double first = 0.0, last = 0.0, worst_norm = 0.0;
  bool world_L_exact = true;
  tumble(s, body.props, 1e-3, n, [&](double t, const RigidBodyState& st) {
    const double err = std::fabs(kinetic_energy(st, body.props) - E0) / E0;
    const long i = std::lround(t / 1e-3);
    if (i <= n / 10) first = std::max(first, err);
    if (i > n - n / 10) last = std::max(last, err);
    world_L_exact = world_L_exact && (st.angular_momentum.array() == L0.array()).all();
    // |R^T L| = |L| iff the orientation stays a rotation.
    const Vector3d Lb = st.orientation.conjugate() * st.angular_momentum;
    worst_norm = std::max(worst_norm, std::fabs(Lb.norm() - L0.norm()) / L0.norm());
  });
  std::printf("[ measured ] dt=1e-3 %s tensor, 1e6 steps: max |dE|/E first 10%% %.3e, last 10%% "
              "%.3e; max | |R^T L| - |L| |/|L| %.1e\n",
              GetParam() ? "full" : "diagonal", first, last, worst_norm);
  // Bounded O(dt^2) error: measured 8.7e-9 = 0.009 (omega dt)^2 (the
  // dominant rotation about L is exact; only the asymmetric remainder is
  // split). Bound 3e-8, a 3.5x margin.
  EXPECT_LT(first, 3e-8);
  // No drift over 1e6 steps: the last tenth no worse than the first (+1 %);
  // measured equal to 4 digits.
  EXPECT_LT(last, 1.01 * first);
  // World-frame L is never touched without torque: conserved bit for bit.
  EXPECT_TRUE(world_L_exact);
  // Orientation normalised every step: body-frame |L| stays |L| to round-off
  // (a few ulps; no accumulation since q is renormalised).
  EXPECT_LT(worst_norm, 1e-14);
}

TEST(RigidBodyTumblingFrames, FullTensorGivesSameWorldMotionAsPrincipalBody) {
  // The same physical body described in two body frames must move the same
  // in the world: orientation of the principal frame q_body Q.
  const Body diagonal(Quaterniond::Identity()), full(tilt());
  RigidBodyState a = start_state(diagonal), b = start_state(full);
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {  // 20 s, through a flip
    initial_integrate(a, diagonal.props, Vector3d::Zero(), Vector3d::Zero(), 1e-3);
    final_integrate(a, diagonal.props, Vector3d::Zero(), Vector3d::Zero(), 1e-3);
    initial_integrate(b, full.props, Vector3d::Zero(), Vector3d::Zero(), 1e-3);
    final_integrate(b, full.props, Vector3d::Zero(), Vector3d::Zero(), 1e-3);
    worst = std::max(worst, (a.orientation * diagonal.Q).angularDistance(b.orientation * full.Q));
  }
  std::printf("[ measured ] full vs diagonal tensor, 2e4 steps: max orientation gap %.1e rad\n",
              worst);
  // Round-off differences (the eigenvectors of the full tensor are accurate
  // to ~1e-15) grow along the near-separatrix orbit; measured 2.4e-12 rad.
  // A frame mix-up (Q vs Q^T, L in the wrong frame) gives O(1).
  EXPECT_LT(worst, 1e-10);
}

// ---------------------------------------------------------------------------
// Order of accuracy against the RK4 reference.

struct Errors {
  double orientation;  // rad
  double momentum;     // |Lb - Lb_ref| / |L|
  double energy;       // max |dE| / E over the run
};

Errors errors_at(const Body& body, double dt, double t_end, const Reference& ref) {
  RigidBodyState s = start_state(body);
  const double E0 = kinetic_energy(s, body.props);
  double energy = 0.0;
  tumble(s, body.props, dt, std::lround(t_end / dt), [&](double, const RigidBodyState& st) {
    energy = std::max(energy, std::fabs(kinetic_energy(st, body.props) - E0) / E0);
  });
  const Vector3d Lb = s.orientation.conjugate() * s.angular_momentum;
  return {s.orientation.angularDistance(ref.q), (Lb - ref.Lb).norm() / ref.Lb.norm(), energy};
}

TEST(RigidBodyConvergence, SecondOrderAgainstRK4) {
  const Body body(tilt());
  const double t_end = 20.0;  // through the first flip (at ~9 s)
  const std::array<double, 4> dts{8e-3, 4e-3, 2e-3, 1e-3};
  // Reference: RK4 at dt_min / 100 = 1e-5; its error, ~t (omega h)^4 ~ 1e-19,
  // is far below round-off (~1e-12 after 2e6 steps) and the errors measured.
  Reference ref = reference_start(body);
  for (long i = 0; i < std::lround(t_end / 1e-5); ++i) ref.step(1e-5);

  std::array<Errors, 4> e{};
  for (size_t i = 0; i < dts.size(); ++i) {
    e[i] = errors_at(body, dts[i], t_end, ref);
    std::printf("[ measured ] dt=%.0e t=20 s: orientation error %.3e rad, |dL_body|/|L| %.3e, "
                "max |dE|/E %.3e\n",
                dts[i], e[i].orientation, e[i].momentum, e[i].energy);
  }
  for (size_t i = 1; i < dts.size(); ++i) {
    const double r_q = e[i - 1].orientation / e[i].orientation;
    const double r_l = e[i - 1].momentum / e[i].momentum;
    const double r_e = e[i - 1].energy / e[i].energy;
    std::printf("[ measured ] ratio dt=%.0e -> %.0e: orientation %.3f, momentum %.3f, energy %.3f\n",
                dts[i - 1], dts[i], r_q, r_l, r_e);
    // Second order: ratio 4 when dt halves (measured 4.000 +- 0.002). The
    // band 3.8..4.2 leaves room for the O(dt^4) remainder and excludes first
    // order (2) and third order (8).
    EXPECT_NEAR(r_q, 4.0, 0.2) << "dt " << dts[i];
    EXPECT_NEAR(r_l, 4.0, 0.2) << "dt " << dts[i];
    EXPECT_NEAR(r_e, 4.0, 0.2) << "dt " << dts[i];
  }
}

// ---------------------------------------------------------------------------
// Why this splitting: against NO_SQUISH (Miller et al. 2002), the symmetric
// splitting of the free rotor into the three principal-axis rotations
// T_k = Lk^2 / (2 Ik), in every one of its 6 axis orders.

void no_squish_step(Quaterniond& q, Vector3d& Lp, const Vector3d& I, const std::array<int, 3>& o,
                    double h) {
  auto flow = [&](int k, double t) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const double th = t * Lp(k) / I(k);
    Quaterniond turn(std::cos(th / 2), 0, 0, 0);
    turn.vec()(k) = std::sin(th / 2);
    q = q * turn;
    const double li = Lp(i), lj = Lp(j);
    Lp(i) = std::cos(th) * li + std::sin(th) * lj;
    Lp(j) = -std::sin(th) * li + std::cos(th) * lj;
  };
  flow(o[0], h / 2);
  flow(o[1], h / 2);
  flow(o[2], h);
  flow(o[1], h / 2);
  flow(o[0], h / 2);
  q.normalize();
}

TEST(RigidBodySplitting, MoreAccurateThanEveryNoSquishOrder) {
  struct Case {
    const char* name;
    Vector3d moments, omega;
  };
  const Case cases[] = {
      {"1,2,3 near axis 1", {1, 2, 3}, {1, 0.1, 0.1}},
      {"1,2,3 near axis 2", {1, 2, 3}, {1e-3, 1, 1e-3}},
      {"1,2,3 near axis 3", {1, 2, 3}, {0.1, 0.1, 1}},
      {"1,2,3 generic", {1, 2, 3}, {0.6, 0.5, 0.7}},
      {"brick 1x2x4", {5.0 / 12, 17.0 / 12, 20.0 / 12}, {0.6, 0.5, 0.7}},
      {"1,5,5.5 near-prolate", {1, 5, 5.5}, {0.6, 0.5, 0.7}},
      {"1,1.1,1.9 near-oblate", {1, 1.1, 1.9}, {0.6, 0.5, 0.7}},
  };
  const std::array<std::array<int, 3>, 6> orders{
      {{2, 1, 0}, {0, 1, 2}, {1, 0, 2}, {0, 2, 1}, {1, 2, 0}, {2, 0, 1}}};
  const double h = 0.01, t_end = 20.0;
  const long n = std::lround(t_end / h);
  for (const Case& c : cases) {
    const PreparedMassProperties p({1.0, c.moments.asDiagonal()});
    const Vector3d L = c.moments.cwiseProduct(c.omega);  // q0 = identity
    Reference ref{c.moments.cwiseInverse().asDiagonal(), Quaterniond::Identity(), L};
    for (long i = 0; i < n * 100; ++i) ref.step(h / 100);

    Quaterniond q = Quaterniond::Identity();
    for (long i = 0; i < n; ++i) free_rotor_step(q, L, p, h);
    const double ours = q.angularDistance(ref.q);
    double best = 1e300;
    for (const auto& o : orders) {
      Quaterniond qn = Quaterniond::Identity();
      for (long i = 0; i < n; ++i) {
        Vector3d Lp = qn.conjugate() * L;
        no_squish_step(qn, Lp, c.moments, o, h);
      }
      best = std::min(best, qn.angularDistance(ref.q));
    }
    Quaterniond qm = Quaterniond::Identity();  // Miller's order: 3, 2, 1, 2, 3
    for (long i = 0; i < n; ++i) {
      Vector3d Lp = qm.conjugate() * L;
      no_squish_step(qm, Lp, c.moments, {2, 1, 0}, h);
    }
    std::printf("[ measured ] %-22s dt=0.01 t=20 s orientation error: ours %.2e, NO_SQUISH "
                "3-2-1 %.2e, best NO_SQUISH order %.2e\n",
                c.name, ours, qm.angularDistance(ref.q), best);
    EXPECT_LT(ours, best) << c.name;
  }
}

// ---------------------------------------------------------------------------
// Cost per body per step (not a pass/fail criterion: see docs/benchmarks.md).
// Run with --gtest_also_run_disabled_tests.
TEST(RigidBodyCost, DISABLED_NanosecondsPerStep) {
  const Body body(tilt());
  std::vector<RigidBodyState> bodies(1000, start_state(body));
  const Vector3d F(0.1, 0.2, -9.8), T(0.01, -0.02, 0.03);
  const int steps = 2000;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) {
    for (auto& s : bodies) initial_integrate(s, body.props, F, T, 1e-5);
    for (auto& s : bodies) final_integrate(s, body.props, F, T, 1e-5);
  }
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0)
                        .count() / (double(steps) * bodies.size());
  std::printf("[ measured ] initial_integrate + final_integrate: %.1f ns per body per step\n", ns);
  EXPECT_GT(bodies[0].orientation.norm(), 0.0);
}

}  // namespace
}  // namespace freestand
