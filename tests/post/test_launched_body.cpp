// launched_body: the events of a ball bouncing with restitution e (closed form),
// sampled and noisy, and the slope uncertainty of a line through flight samples.

#include "launched_body.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace freestand {
namespace {

const double kG = 9.81;

// Height of a ball dropped from h (at rest at t = 0) that bounces with restitution e: touchdowns
// at t1 = sqrt(2h/g), then every 2 e^i v1 / g later, apex heights e^(2i) h.
double bouncing_height(double t, double h, double e) {
  double v = std::sqrt(2 * kG * h), start = v / kG;  // speed at the first touchdown, its time
  if (t < start) return h - 0.5 * kG * t * t;
  for (int i = 0; i < 50; ++i) {
    v *= e;
    const double flight = 2 * v / kG;
    if (t < start + flight) return v * (t - start) - 0.5 * kG * (t - start) * (t - start);
    start += flight;
  }
  return 0;
}

TEST(LaunchedBody, TouchdownsAndBouncesOfABouncingBall) {
  const double h = 0.1, e = 0.5, noise = 5e-5, step = 1.0 / 148;
  std::mt19937 random(3);
  std::normal_distribution<double> white(0, noise);
  std::vector<double> t, z;
  for (int k = 0; k < 148; ++k) t.push_back(k * step), z.push_back(bouncing_height(t.back(), h, e) - h + white(random));
  const LaunchedEvents ev = launched_events(t, {&z}, {}, z, 4 * noise, 0.002, 0.035);
  const double t1 = std::sqrt(2 * h / kG), v1 = std::sqrt(2 * kG * h);
  ASSERT_GE(ev.touchdowns.size(), 3u);
  // A touchdown is the lowest sample: within one step of the true instant.
  EXPECT_NEAR(ev.touchdowns[0], t1, step);
  EXPECT_NEAR(ev.touchdowns[1], t1 + 2 * e * v1 / kG, step);
  EXPECT_NEAR(ev.touchdowns[2], t1 + 2 * (e + e * e) * v1 / kG, step);
  // The sampled apex is below the true one by at most (g/8) step^2 (a parabola sampled within
  // half a step of its vertex), plus the noise.
  const double sampling = kG / 8 * step * step + 4 * noise;
  EXPECT_NEAR(ev.bounce_heights[0], e * e * h, sampling);
  EXPECT_NEAR(ev.bounce_heights[1], std::pow(e, 4) * h, sampling);
  // At rest once the bounces are below the 2 mm band: after the bounce of e^(2i) h < 2 mm.
  EXPECT_LT(ev.rest_time, t1 + 2 * (e + e * e + std::pow(e, 3)) * v1 / kG + step);
  EXPECT_GT(ev.rest_time, t1);
}

TEST(LaunchedBody, ALaunchUpwardIsNoBounce) {
  // Thrown up at 1 m/s from 0.1 m: the apex of the throw is no bounce; the first touchdown is
  // at the root of 0.1 + t - g t^2 / 2 = 0.
  const double step = 1.0 / 148;
  std::vector<double> t, z;
  for (int k = 0; k < 100; ++k) {
    t.push_back(k * step);
    z.push_back(std::max(0.1 + t.back() - 0.5 * kG * t.back() * t.back(), 0.0) - 0.1);
  }
  const LaunchedEvents ev = launched_events(t, {&z}, {}, z, 2e-4, 0.002, 0.035);
  const double landing = (1 + std::sqrt(1 + 2 * kG * 0.1)) / kG;
  ASSERT_EQ(ev.touchdowns.size(), 0u) << "it never rises again: no touchdown is confirmed";
  EXPECT_TRUE(ev.bounce_heights.empty());
  EXPECT_NEAR(ev.rest_time, landing, step);
}

TEST(LaunchedBody, FlightRateUncertaintyIsTheScatterOfFittedSlopes) {
  const double noise = 1e-3, step = 0.01;
  const int n = 8;
  std::mt19937 random(5);
  std::normal_distribution<double> white(0, noise);
  double sum = 0, sum2 = 0;
  const int trials = 4000;
  for (int trial = 0; trial < trials; ++trial) {
    double st = 0, sy = 0, stt = 0, sty = 0;
    for (int k = 0; k < n; ++k) {
      const double tk = k * step, y = 1.2 * tk + white(random);
      st += tk, sy += y, stt += tk * tk, sty += tk * y;
    }
    const double slope = (n * sty - st * sy) / (n * stt - st * st);
    sum += slope, sum2 += slope * slope;
  }
  const double sd = std::sqrt(sum2 / trials - std::pow(sum / trials, 2));
  // 4000 draws: the sample s.d. is good to 1/sqrt(2 x 4000) = 1.1 %; 5 % is over 4 of those.
  EXPECT_NEAR(sd / flight_rate_sd(noise, n, step), 1.0, 0.05);
}

TEST(LaunchedBody, LaunchedMeansAnInitialVelocityOrSpin) {
  EXPECT_TRUE(is_launched({{"velocity", {1.0, 0.0, 0.0}}}));
  EXPECT_TRUE(is_launched({{"omega", {0.0, 0.0, 4.0}}}));
  EXPECT_FALSE(is_launched({{"velocity", {0.0, 0.0, 0.0}}}));
  EXPECT_FALSE(is_launched({{"name", "block"}}));
}

}  // namespace
}  // namespace freestand
