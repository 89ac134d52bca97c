// Analytic table motions: closed-form v and d are the integrals of a (checked
// by quadrature), rest before t = 0, free flight after the end, peaks, errors.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "freestand/input_error.h"
#include "freestand/table_motion.h"

namespace freestand {
namespace {

constexpr double kPi = 3.14159265358979323846;

AnalyticMotionSpec spec(const std::string& kind, double amplitude, double frequency) {
  AnalyticMotionSpec s;
  s.kind = kind;
  s.amplitude = amplitude;
  s.frequency = frequency;
  return s;
}

// Largest deviation of v from the running integral of `accel`, and of d from
// that of v, relative to max|v| and max|d|, on [0, T]. Simpson's rule with
// step h errs by h^4/180 T max|f''''|: for the smooth motions below
// (f <= 5 Hz, h = 1e-4 s) that is ~(2 pi f h)^4 / 180 ~ 1e-14 relative.
struct IntegralCheck {
  double velocity = 0.0;      // max |v - int a| / max |v|
  double displacement = 0.0;  // max |d - int v| / max |d|
};

IntegralCheck check_integrals(const AxisMotion& m, double T, double h,
                              const std::function<double(double)>& accel) {
  const int n = 2 * static_cast<int>(std::ceil(T / (2 * h)));  // even
  // Node k; the last is T itself so that no panel reaches past the end.
  // at(0) is rest by convention, so the first node is 0+ (smallest double).
  const auto node = [&](int k) { return k == n ? T : k == 0 ? 1e-300 : T * k / n; };
  double v_int = 0.0, d_int = 0.0, dv = 0.0, dd = 0.0, vmax = 0.0, dmax = 0.0;
  for (int i = 0; i < n; i += 2) {  // one Simpson panel [node i, node i + 2]
    const double t0 = node(i), t1 = node(i + 1), t2 = node(i + 2);
    const double w = (t2 - t0) / 6;
    v_int += w * (accel(t0) + 4 * accel(t1) + accel(t2));
    d_int += w * (m.at(t0).velocity + 4 * m.at(t1).velocity + m.at(t2).velocity);
    const AxisState s2 = m.at(t2);
    dv = std::max(dv, std::abs(s2.velocity - v_int));
    dd = std::max(dd, std::abs(s2.displacement - d_int));
    vmax = std::max(vmax, std::abs(s2.velocity));
    dmax = std::max(dmax, std::abs(s2.displacement));
  }
  return {dv / vmax, dd / dmax};
}

IntegralCheck check_integrals(const AxisMotion& m, double T, double h) {
  return check_integrals(m, T, h, [&m](double t) { return m.at(t).acceleration; });
}

// at(t) for t <= 0 is rest.
void expect_rest_before_zero(const AxisMotion& m) {
  for (double x : {-5.0, -1e-12, 0.0}) {
    const AxisState s = m.at(x);
    EXPECT_EQ(s.acceleration, 0.0);
    EXPECT_EQ(s.velocity, 0.0);
    EXPECT_EQ(s.displacement, 0.0);
  }
}

// After the end: a = 0, constant v, d growing linearly (exact arithmetic).
void expect_free_flight_after_end(const AxisMotion& m) {
  const double T = m.duration();
  const AxisState end = m.at(T), later = m.at(T + 2.0);
  EXPECT_EQ(later.acceleration, 0.0);
  EXPECT_EQ(later.velocity, end.velocity);
  EXPECT_NEAR(later.displacement, end.displacement + 2.0 * end.velocity,
              1e-14 * (std::abs(end.displacement) + std::abs(end.velocity)));
}

// Tolerance 1e-9 for the closed forms: Simpson with h = 1e-4 s errs by
// ~(2 pi f h)^4 / 180 ~ 1e-14 of the value for f <= 5 Hz; the running sums of
// ~1e5 panels add round-off ~1e5 eps ~ 1e-11. A wrong constant of
// integration or sign would be O(1).
constexpr double kClosedFormTolerance = 1e-9;

TEST(AnalyticMotion, SineIntegralsAndDrift) {
  auto s = spec("sine", 3.0, 2.0);
  s.duration = 2.2;
  const auto m = make_analytic_motion(s);
  const IntegralCheck c = check_integrals(*m, 2.2, 1e-4);
  EXPECT_LT(c.velocity, kClosedFormTolerance);
  EXPECT_LT(c.displacement, kClosedFormTolerance);
  expect_rest_before_zero(*m);
  expect_free_flight_after_end(*m);
  EXPECT_DOUBLE_EQ(m->peak_acceleration(), 3.0);
  // Mean velocity A / w: after whole periods v = 0 and d = A T / w.
  const double w = 2 * kPi * 2.0;
  EXPECT_NEAR(m->at(2.0).velocity, 0.0, 1e-14);
  EXPECT_NEAR(m->at(2.0).displacement, 3.0 * 2.0 / w, 1e-14);
}

TEST(AnalyticMotion, UnlimitedSine) {
  const auto m = make_analytic_motion(spec("sine", 1.0, 1.0));
  EXPECT_TRUE(std::isinf(m->duration()));
  EXPECT_NEAR(m->at(1000.25).acceleration, 1.0, 1e-9);  // sin(2 pi 1000.25): phase round-off ~1e-12
}

TEST(AnalyticMotion, ShortSinePeaksAtItsEnd) {
  auto s = spec("sine", 2.0, 1.0);
  s.duration = 0.1;  // w T = 0.63 < pi/2
  EXPECT_DOUBLE_EQ(make_analytic_motion(s)->peak_acceleration(), 2.0 * std::sin(2 * kPi * 0.1));
}

TEST(AnalyticMotion, OneSineEndsAtRestDisplaced) {
  const auto m = make_analytic_motion(spec("onesine", 2.0, 4.0));
  EXPECT_DOUBLE_EQ(m->duration(), 0.25);
  const IntegralCheck c = check_integrals(*m, 0.25, 1e-5);
  EXPECT_LT(c.velocity, kClosedFormTolerance);
  EXPECT_LT(c.displacement, kClosedFormTolerance);
  expect_rest_before_zero(*m);
  expect_free_flight_after_end(*m);
  const AxisState end = m->at(1.0);
  EXPECT_NEAR(end.velocity, 0.0, 1e-15);
  EXPECT_NEAR(end.displacement, 2.0 * 0.25 / (2 * kPi * 4.0), 1e-15);  // A T / w
}

TEST(AnalyticMotion, RickerIntegralsPeakAndDefaultCentre) {
  const auto m = make_analytic_motion(spec("ricker", 5.0, 2.0));
  EXPECT_DOUBLE_EQ(m->duration(), 2 * 1.5 / 2.0);  // 2 ts, ts = 1.5 / f
  const IntegralCheck c = check_integrals(*m, m->duration(), 1e-4);
  EXPECT_LT(c.velocity, kClosedFormTolerance);
  EXPECT_LT(c.displacement, kClosedFormTolerance);
  expect_rest_before_zero(*m);
  expect_free_flight_after_end(*m);
  EXPECT_DOUBLE_EQ(m->at(0.75).acceleration, 5.0);  // peak at ts
  EXPECT_DOUBLE_EQ(m->peak_acceleration(), 5.0);
  // The cut tails: a(0+) = A (1 - 2 u0^2) exp(-u0^2), u0 = 1.5 pi: ~ -1e-8 A.
  const double u0 = 1.5 * kPi;
  EXPECT_NEAR(m->at(1e-12).acceleration, 5.0 * (1 - 2 * u0 * u0) * std::exp(-u0 * u0), 1e-15);
}

TEST(AnalyticMotion, RickerWithGivenCentre) {
  auto s = spec("ricker", -1.0, 1.0);
  s.width = 2.0;
  const auto m = make_analytic_motion(s);
  EXPECT_DOUBLE_EQ(m->duration(), 4.0);
  EXPECT_DOUBLE_EQ(m->at(2.0).acceleration, -1.0);
  const IntegralCheck c = check_integrals(*m, 4.0, 1e-4);
  EXPECT_LT(c.velocity, kClosedFormTolerance);
  EXPECT_LT(c.displacement, kClosedFormTolerance);
}

// Rectangle: a = A, v = A t, d = A t^2 / 2 exactly, then v = A W.
TEST(AnalyticMotion, Rectangle) {
  auto s = spec("rectangle", 2.0, 0.0);
  s.width = 0.5;
  const auto m = make_analytic_motion(s);
  EXPECT_EQ(m->at(0.3).acceleration, 2.0);
  EXPECT_DOUBLE_EQ(m->at(0.3).velocity, 0.6);
  EXPECT_DOUBLE_EQ(m->at(0.3).displacement, 0.09);
  EXPECT_DOUBLE_EQ(m->at(1.5).velocity, 1.0);
  EXPECT_DOUBLE_EQ(m->at(1.5).displacement, 0.25 + 1.0);
  expect_rest_before_zero(*m);
  expect_free_flight_after_end(*m);
}

// The sweep is sampled so that |a - chirp| <= 1e-4 A (see make_sweep). Its
// v and d are exact integrals of the samples, so against the integrals of
// the true chirp they err like the trapezoid rule: (w h)^2 / 12 of max|v|
// (see SampledAxisMotion's sine test), i.e. 8/12 of that bound; 1e-4 it is.
TEST(AnalyticMotion, SweepFollowsTheChirp) {
  auto s = spec("sweep", 1.5, 1.0);
  s.frequency_end = 5.0;
  s.duration = 4.0;
  const auto m = make_analytic_motion(s);
  EXPECT_DOUBLE_EQ(m->duration(), 4.0);
  const auto chirp = [](double t) {
    return 1.5 * std::sin(2 * kPi * (1.0 * t + (5.0 - 1.0) * t * t / (2 * 4.0)));
  };
  for (double x = 0.001; x < 4.0; x += 0.00123)
    EXPECT_NEAR(m->at(x).acceleration, chirp(x), 1e-4 * 1.5) << x;
  const IntegralCheck c = check_integrals(*m, 4.0, 1e-4, chirp);
  EXPECT_LT(c.velocity, 1e-4);
  EXPECT_LT(c.displacement, 1e-4);
  expect_rest_before_zero(*m);
  expect_free_flight_after_end(*m);
}

TEST(AnalyticMotion, RejectsBadSpecs) {
  EXPECT_THROW(make_analytic_motion(spec("square", 1.0, 1.0)), InputError);
  EXPECT_THROW(make_analytic_motion(spec("sine", 0.0, 1.0)), InputError);   // no amplitude
  EXPECT_THROW(make_analytic_motion(spec("sine", 1.0, 0.0)), InputError);   // no frequency
  EXPECT_THROW(make_analytic_motion(spec("rectangle", 1.0, 0.0)), InputError);  // no width
  EXPECT_THROW(make_analytic_motion(spec("sweep", 1.0, 1.0)), InputError);  // no duration
  auto onesine = spec("onesine", 1.0, 1.0);
  onesine.duration = 3.0;  // not a parameter of onesine
  EXPECT_THROW(make_analytic_motion(onesine), InputError);
  auto ricker = spec("ricker", 1.0, 1.0);
  ricker.width = -1.0;
  EXPECT_THROW(make_analytic_motion(ricker), InputError);
}

}  // namespace
}  // namespace freestand
