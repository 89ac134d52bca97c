// Tests of the small signal tools that the analysis and the diagnosis share.

#include "signal_tools.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace freestand::signal {
namespace {

// The sample s.d. divides by n - 1 (unbiased variance): {1, 2, 3, 4} has mean 2.5 and squared
// deviations summing to 5, so sqrt(5 / 3). One value has no spread to estimate: NaN, not 0.
TEST(SignalTools, SampleSdDividesByNMinusOneAndNeedsTwoValues) {
  EXPECT_DOUBLE_EQ(sample_sd({1.0, 2.0, 3.0, 4.0}), std::sqrt(5.0 / 3.0));
  EXPECT_DOUBLE_EQ(sample_sd({7.0, 7.0}), 0.0);
  EXPECT_TRUE(std::isnan(sample_sd({1.0})));
  EXPECT_TRUE(std::isnan(sample_sd({})));
}

// A table's travel under a broadband record (80 tones, 0.3-20 Hz, acceleration falling as
// 1 / (1 + (f / 5 Hz)^2), 1 m/s^2 rms, random phases), its exact acceleration beside it.
struct Travel {
  std::vector<double> d, a;
};
Travel broadband_travel(std::size_t n, double dt) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> phase(0, 2 * M_PI);
  Travel out{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
  for (int j = 0; j < 80; ++j) {
    const double f = 0.3 * std::pow(20 / 0.3, j / 79.0), w = 2 * M_PI * f, amplitude = 0.3 / (1 + f * f / 25),
                 p = phase(random);
    for (std::size_t k = 0; k < n; ++k) {
      out.a[k] += amplitude * std::sin(w * k * dt + p);
      out.d[k] -= amplitude / (w * w) * std::sin(w * k * dt + p);
    }
  }
  return out;
}

// rms of the central second difference of y against a, away from the ends.
double acceleration_error(const std::vector<double>& y, const std::vector<double>& a, double dt) {
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t k = 10; k + 10 < y.size(); ++k, ++count)
    sum += std::pow((y[k + 1] - 2 * y[k] + y[k - 1]) / (dt * dt) - a[k], 2);
  return std::sqrt(sum / count);
}

// The reference is the best brick wall chosen knowing the truth: every cut-off bin from 1 Hz
// to 30 Hz tried on the same noisy travel. The rule, which knows only the noise, should come
// near it: on a spectrum falling as f^-4 the bins it keeps end where a 1-Hz average of the power
// crosses about 2.5 times the noise's, and that average scatters by about 1 / sqrt(21) here,
// which moves the end by a few bins (measured: 1.03-1.05 times the best wall for these three
// noise draws). Without the cut the three-point second difference is noise: 0.5 mm at 200 Hz
// is 0.5e-3 sqrt(6) / dt^2 = 49 m/s^2 rms.
TEST(SignalTools, CutNoiseComesNearTheBestBrickWallForADifferentiatedTravel) {
  const double dt = 0.005, sigma = 5e-4;
  const Travel truth = broadband_travel(4000, dt);
  for (unsigned seed : {11u, 12u, 13u}) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal(0, sigma);
    std::vector<double> measured = truth.d;
    for (double& v : measured) v += normal(random);
    const NoiseCut cut = cut_noise(measured, dt, sigma);
    const double error = acceleration_error(cut.values, truth.a, dt);
    double best = INFINITY, best_hz = 0;
    for (double hz = 1; hz < 30; hz += 0.05)  // every bin: 0.05 Hz is the DFT's step here
      if (const double e = acceleration_error(band_limited(measured, dt, [&](double f) { return f < hz; }), truth.a, dt); e < best)
        best = e, best_hz = hz;
    EXPECT_LT(error, 1.25 * best) << "seed " << seed << ": kept up to " << cut.highest_kept_hz << " Hz, best at " << best_hz;
    EXPECT_GT(acceleration_error(measured, truth.a, dt), 40.0);
    EXPECT_LT(error, 0.3);  // of a 1 m/s^2 record
  }
}

// No noise stated: the series as it is, cut nowhere below Nyquist.
TEST(SignalTools, CutNoiseWithoutNoiseLeavesTheSeries) {
  const double dt = 0.005;
  const Travel truth = broadband_travel(2000, dt);
  const NoiseCut none = cut_noise(truth.d, dt, 0);
  EXPECT_EQ(none.values, truth.d);
  EXPECT_DOUBLE_EQ(none.highest_kept_hz, 100.0);
}

// A line is its own linear bridge: the lost samples inside fall on it, those before the first and
// after the last finite sample take its value there; the longest run spans from the finite
// sample before it to the one after (or to the record's end).
TEST(SignalTools, BridgeLostJoinsNeighboursAndHoldsTheEnds) {
  const std::vector<double> t = {0, 1, 2, 3, 4, 5, 6, 7};
  const std::vector<double> y = {kNaN, 2, kNaN, kNaN, 8, 10, kNaN, kNaN};  // 2 t where finite
  EXPECT_EQ(bridge_lost(t, y), (std::vector<double>{2, 2, 4, 6, 8, 10, 10, 10}));
  const LostSamples lost = lost_samples(t, y);
  EXPECT_EQ(lost.count, 5u);
  EXPECT_DOUBLE_EQ(lost.longest, 3.0);  // 1 to 4
  EXPECT_DOUBLE_EQ(lost.longest_at, 2.0);
  EXPECT_EQ(lost_samples(t, bridge_lost(t, y)).count, 0u);
  EXPECT_TRUE(std::isnan(bridge_lost({0, 1}, {kNaN, kNaN})[0]));
}

}  // namespace
}  // namespace freestand::signal
