// comparison: synthetic recordings made from a known simulation with a known
// time offset, gain, bias, noise and lost samples; the metrics must recover
// them within the tolerances their estimators allow.

#include "comparison.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "../reference/housner.h"
#include "freestand/input_error.h"
#include "synthetic_motion.h"

namespace freestand::comparison {
namespace {

// A "simulation": two decaying tones, sampled at 1 kHz on its own time base.
double simulated_signal(double t) {
  return std::exp(-0.2 * t) * (0.05 * std::sin(2 * M_PI * 1.3 * t) + 0.02 * std::sin(2 * M_PI * 3.1 * t + 0.4));
}
double simulated_rate(double t) {
  const double e = std::exp(-0.2 * t);
  return -0.2 * simulated_signal(t) +
         e * (0.05 * 2 * M_PI * 1.3 * std::cos(2 * M_PI * 1.3 * t) + 0.02 * 2 * M_PI * 3.1 * std::cos(2 * M_PI * 3.1 * t + 0.4));
}

struct Series {
  std::vector<double> t, y;
};

Series sample(double step, double duration, const std::function<double(double)>& f) {
  Series s;
  for (long k = 0; k * step <= duration; ++k) {
    s.t.push_back(k * step);
    s.y.push_back(f(k * step));
  }
  return s;
}

// recording(t) = gain * simulation(t - offset) + bias + noise, at 200 Hz, with
// every 50th sample and a 0.1 s block lost.
TEST(Comparison, RecoversOffsetGainAndBias) {
  const double gain = 0.9, offset = 0.037, bias = 0.002, noise = 1e-3, step = 0.005, duration = 10;
  const Series sim = sample(0.001, duration, simulated_signal);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0, noise);
  Series rec = sample(step, duration, [&](double t) { return gain * simulated_signal(t - offset) + bias + normal(rng); });
  int lost = 0;
  for (std::size_t i = 0; i < rec.t.size(); ++i)
    if (i % 50 == 7 || (rec.t[i] >= 4.0 && rec.t[i] < 4.1)) rec.y[i] = NAN, ++lost;

  ComparisonParameters parameters;
  parameters.noise = noise;
  const ChannelComparison c = compare_channel(rec.t, rec.y, sim.t, sim.y, parameters);
  EXPECT_EQ(c.samples, static_cast<int>(rec.t.size()) - lost);

  // Offset: Cramer-Rao bound of a delay in white noise, sd = noise /
  // (gain sqrt(sum s'(t)^2)), over the recording's samples; the parabola
  // through the correlation peak errs by at most (dt / 2)(w dt)^2 / 12 for
  // the highest tone w (~1e-7 s here); linear interpolation of the 1 kHz
  // simulation by s'' (1 ms)^2 / 8 (~1e-6 of the signal). 4 sd of the first.
  double sum_rate2 = 0;
  for (double t : rec.t) sum_rate2 += std::pow(simulated_rate(t - offset), 2);
  const double offset_sd = noise / (gain * std::sqrt(sum_rate2));
  const double w = 2 * M_PI * 3.1;
  EXPECT_NEAR(c.offset_gain.offset, offset, 4 * offset_sd + 0.5 * step * std::pow(w * step, 2) / 12);
  // Gain: least-squares sd (reported) for the stated noise; an offset error
  // d changes it by a factor cos(w d) ~ 1 - 1e-5: 4 sd.
  EXPECT_NEAR(c.offset_gain.gain, gain, 4 * c.offset_gain.gain_sd);
  // Bias: sd noise / sqrt(N) for a zero-mean regressor: 4 of those.
  EXPECT_NEAR(c.offset_gain.bias, bias, 4 * noise / std::sqrt(c.samples));
  EXPECT_GT(c.offset_gain.correlation, 0.99);
}

TEST(Comparison, PeakErrorAndResidualsOnACommonTimeBase) {
  const Series sim = sample(0.005, 5, [](double t) { return simulated_signal(t) + (t > 4 ? 0.012 : 0.0); });
  const Series rec = sample(0.005, 5, [](double t) { return 1.1 * simulated_signal(t) + (t > 4 ? 0.01 : 0.0); });
  const ChannelComparison c = compare_channel(rec.t, rec.y, sim.t, sim.y);
  // Same samples on both sides: the peaks are the same sample, so the error is
  // exactly 1 / 1.1 - 1 (to rounding).
  EXPECT_NEAR(c.peak_error_percent, 100 * (1 / 1.1 - 1), 1e-9);
  // Residual window: the last 10 % (4.5-5 s), where sim - rec = 0.002 - 0.1 s(t).
  double expected = 0;
  int n = 0;
  for (double t = 4.5; t <= 5 + 1e-9; t += 0.005, ++n) expected += 0.002 - 0.1 * simulated_signal(t);
  EXPECT_NEAR(c.residual_difference, expected / n, 1e-4);  // window edges: +-1 sample of 0.1 s(t) <= 5e-3 / 100 samples
}

// Divergence: identical until 2 s, then the recording steps by D = 0.3 peak.
// The running RMS over the window T is D sqrt(f) once a fraction f of it lies
// after the step; it exceeds 0.1 peak when f > (0.1 / 0.3)^2 = 1/9, i.e. at
// 2 s + T / 9, found at the next sample.
TEST(Comparison, DivergenceTimeOfAStep) {
  const Series sim = sample(0.005, 5, simulated_signal);
  double peak = 0;
  for (double y : sim.y) peak = std::max(peak, std::fabs(y));
  const Series rec = sample(0.005, 5, [&](double t) { return simulated_signal(t) + (t >= 2 ? 0.3 * peak : 0.0); });
  ComparisonParameters parameters;
  parameters.max_lag = 0.05;
  const ChannelComparison c = compare_channel(rec.t, rec.y, sim.t, sim.y, parameters);
  EXPECT_NEAR(c.divergence_threshold, 0.1 * peak, 1e-15);
  EXPECT_NEAR(c.divergence_time, 2 + parameters.divergence_window / 9, 0.005 + 1e-9);
  const ChannelComparison same = compare_channel(sim.t, sim.y, sim.t, sim.y, parameters);
  EXPECT_TRUE(std::isnan(same.divergence_time));
  EXPECT_EQ(same.nrmse, 0.0);
}

// NRMSE of a recording that is the simulation plus white noise: noise /
// peak, within the sampling sd of an RMS over N samples, 1 / sqrt(2 N): 4 of those.
TEST(Comparison, NormalisedRmsErrorOfNoise) {
  const double noise = 2e-3;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0, noise);
  const Series sim = sample(0.005, 10, simulated_signal);
  const Series rec = sample(0.005, 10, [&](double t) { return simulated_signal(t) + normal(rng); });
  const ChannelComparison c = compare_channel(rec.t, rec.y, sim.t, sim.y);
  const double expected = noise / c.peak_recorded;
  EXPECT_NEAR(c.nrmse, expected, 4 * expected / std::sqrt(2.0 * rec.t.size()));
}

// Dominant frequency of a tone between bins: the log-parabola through a
// Hann-windowed peak is biased by a few hundredths of a bin (Grandke 1983;
// measured at most 0.016 bin over 20 fractional positions): 0.05 bin.
// Centroid of a pure tone: the leakage is symmetric
// about the tone except for its image at -f, negligible 20 bins away: 0.05 bin.
TEST(Comparison, SpectrumOfTonesBetweenBins) {
  const double step = 0.005, duration = 20;  // bin width 1 / 20 Hz
  const double bin = 1 / (duration + step);
  for (double fraction : {0.0, 0.17, 0.33, 0.5, 0.71, 0.9}) {
    const double f = (40 + fraction) * bin;
    const Series s = sample(step, duration, [&](double t) { return std::sin(2 * M_PI * f * t + 0.3); });
    const Spectrum spectrum_found = spectrum(s.t, s.y);
    EXPECT_NEAR(spectrum_found.dominant_frequency, f, 0.05 * bin) << fraction;
    EXPECT_NEAR(spectrum_found.centroid, f, 0.05 * bin) << fraction;
  }
}

// Impact decay of two free-rocking records with different restitution: the
// median ratios are told apart and each matches its own r.
TEST(Comparison, ImpactDecayOfTwoRockingRecords) {
  const reference::HousnerBlock block{0.1, 0.5};
  const analysis::BodyGeometry geometry{0.1, 0.1, 0.5};
  analysis::AnalysisParameters parameters;
  parameters.angle_noise = parameters.length_noise = 1e-6;
  auto motion_of = [&](double r, double step) {
    const auto rocking = test::free_rocking(block.p(), block.alpha(), r, 0.1, step, 3.0);
    analysis::BodyMotion motion;
    motion.time = rocking.t;
    motion.channels[analysis::kRockX] = rocking.theta;
    return motion;
  };
  const analysis::BodyMotion recorded = motion_of(block.e(), 0.005), simulated = motion_of(0.85, 0.002);
  const BodyComparison c = compare_body(recorded, simulated, geometry, parameters);
  // Tolerance of the ratio from a one-sided quadratic fit: 0.2 p^2 W^2
  // (test_motion_analysis.cpp explains it).
  const double tolerance = 0.2 * std::pow(block.p() * parameters.impact_window, 2);
  EXPECT_NEAR(c.decay[0].recorded_median, block.e(), tolerance);
  EXPECT_NEAR(c.decay[0].simulated_median, 0.85, tolerance);
  EXPECT_GE(c.decay[0].recorded_ratios.size(), 5u);
  EXPECT_EQ(c.channels[analysis::kRockX].samples, static_cast<int>(recorded.time.size()));
  EXPECT_EQ(c.channels[analysis::kSlideX].samples, 0);  // in neither
  EXPECT_TRUE(c.decay[1].recorded_ratios.empty());
}

TEST(Comparison, BadSeriesAreAnInputError) {
  EXPECT_THROW(compare_channel({0, 1, 2}, {0, 1}, {0, 1, 2}, {0, 1, 2}), InputError);
  EXPECT_THROW(compare_channel({0, 1, 2}, {0, 1, 2}, {0, 2, 1}, {0, 1, 2}), InputError);
}

}  // namespace
}  // namespace freestand::comparison
