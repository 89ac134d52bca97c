// motion_analysis against independent references: Housner free rocking
// (tests/reference/housner.h), Newmark sliding (tests/reference/newmark.h),
// the channel kernels of src/freestand/rocking_angles.h, and lost samples.

#include "motion_analysis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "freestand/input_error.h"
#include "freestand/rocking_angles.h"
#include "../reference/housner.h"
#include "../reference/newmark.h"
#include "synthetic_motion.h"

namespace freestand::analysis {
namespace {

using reference::HousnerBlock;

constexpr double kSampleStep = 0.005;  // 200 Hz, the format's typical sampling

// A 0.2 m x 1.0 m block (b = 0.1, h = 0.5): alpha = 0.197 rad, p = 3.8 rad/s, r = 0.942.
const HousnerBlock kBlock{0.1, 0.5};

BodyGeometry geometry_of(const HousnerBlock& block) { return {block.half_width, block.half_width, block.half_height}; }

// Rocking in x only; slide_x and uplift follow from rocking on the base edges
// (base centre sgn(theta) b (1 - cos theta), COM rise h (cos theta - 1) + b sin|theta|).
BodyMotion rocking_motion(const test::SyntheticRocking& rocking, const HousnerBlock& block, double noise,
                          unsigned seed) {
  BodyMotion motion;
  motion.time = rocking.t;
  std::mt19937 rng(seed);
  std::normal_distribution<double> angle_noise(0, noise), length_noise(0, noise);
  const double b = block.half_width, h = block.half_height, theta0 = rocking.theta.front();
  for (std::size_t i = 0; i < rocking.t.size(); ++i) {
    const double theta = rocking.theta[i];
    auto rise = [&](double a) { return h * (std::cos(a) - 1) + b * std::sin(std::fabs(a)); };
    motion.channels[kRockX].push_back(theta + angle_noise(rng));
    motion.channels[kRockY].push_back(angle_noise(rng));
    motion.channels[kTwist].push_back(angle_noise(rng));
    motion.channels[kSlideX].push_back((theta > 0 ? 1 : -1) * b * (1 - std::cos(theta)) + length_noise(rng));
    motion.channels[kSlideY].push_back(length_noise(rng));
    motion.channels[kUplift].push_back(rise(theta) - rise(theta0) + length_noise(rng));
  }
  return motion;
}

// Expected impact times from Housner's amplitude map and quarter periods.
std::vector<double> housner_impact_times(const HousnerBlock& block, double theta0, int n) {
  const std::vector<double> amplitudes = reference::amplitude_map(block, theta0, n);
  std::vector<double> times{reference::quarter_period(block, theta0)};
  for (int k = 0; k + 1 < n; ++k) times.push_back(times.back() + 2 * reference::quarter_period(block, amplitudes[k]));
  return times;
}

// Checks impacts, ratios and amplitudes of a free-rocking record against
// Housner, for the first `count` impacts. Tolerances:
// - impact time: the zero of a one-sided quadratic fit over W errs by the
//   end value of the cubic's residual, theta''' W^3 / 120 (P3 residual 1/20 of
//   W^3 theta''' / 6), over |omega|, with theta''' <= p^2 |omega|; noise: the
//   end value of a quadratic fit to N = W / dt samples has sd 3 sd / sqrt(N),
//   the mean of two sides sqrt(2) less, over |omega|: 4 of those;
// - omega: a one-sided quadratic fit over a window W leaves the cubic term:
//   for theta''' <= p^2 |omega| the slope errs by 0.1 theta''' W^2 (Legendre
//   P3 residual of t^3 on [0, W]: slope 0.6 of W^2 theta''' / 6), relative
//   0.1 p^2 W^2 on each side, so 0.2 p^2 W^2 on the ratio; plus 4 reported sd;
// - amplitude: the 5-sample parabola errs by O(p^4 alpha dt^4) ~ 1e-9 rad
//   without noise; with noise its fitted value has sd 0.70 sd(angle) (17/35
//   variance factor of a 5-point quadratic at the centre): 4 of those. When
//   samples around a peak are lost the parabola spans up to `peak_span` s and
//   errs by the quartic term, p^4 sin(alpha) (peak_span / 2)^4 / 24.
void expect_housner(const RockingImpacts& found, const HousnerBlock& block, double theta0, double noise,
                    const AnalysisParameters& parameters, int count, double peak_span = 4 * kSampleStep) {
  const std::vector<double> times = housner_impact_times(block, theta0, count);
  const std::vector<double> amplitudes = reference::amplitude_map(block, theta0, count);
  const double p = block.p(), e = block.e();
  ASSERT_GE(found.impacts.size(), static_cast<std::size_t>(count));
  EXPECT_NEAR(found.housner_ratio, e, 1e-15);
  double previous_amplitude = theta0;
  for (int k = 0; k < count; ++k) {
    const Impact& impact = found.impacts[k];
    const double omega = p * std::sqrt(2 * (std::cos(block.alpha() - previous_amplitude) - std::cos(block.alpha())));
    const double window = parameters.impact_window;
    const double time_tolerance = p * p * std::pow(window, 3) / 120 +
                                  4 * 3 * noise / std::sqrt(2 * window / kSampleStep) / omega;
    EXPECT_NEAR(impact.time, times[k], time_tolerance) << "impact " << k;
    const double ratio_tolerance = 0.2 * p * p * window * window * e + 4 * impact.ratio_sd;
    EXPECT_NEAR(impact.ratio, e, ratio_tolerance) << "impact " << k;
    EXPECT_NEAR(std::fabs(impact.omega_before), omega, 0.1 * p * p * window * window * omega + 4 * impact.omega_before_sd)
        << "impact " << k;
    const double amplitude_tolerance = (noise > 0 ? 4 * 0.70 * noise : 1e-9) +
                                       std::pow(p, 4) * std::sin(block.alpha()) * std::pow(peak_span / 2, 4) / 24;
    EXPECT_NEAR(impact.amplitude_before, previous_amplitude, amplitude_tolerance) << "impact " << k;
    EXPECT_NEAR(impact.amplitude_after, amplitudes[k], amplitude_tolerance) << "impact " << k;
    if (k + 1 < count) {
      EXPECT_NEAR(found.half_cycles[k].amplitude, amplitudes[k], amplitude_tolerance);
      EXPECT_NEAR(found.half_cycles[k].end - found.half_cycles[k].start, times[k + 1] - times[k], 2 * time_tolerance);
    }
    previous_amplitude = amplitudes[k];
  }
}

TEST(MotionAnalysis, SyntheticRockingReproducesItsOwnImpacts) {
  // The generator against Housner's closed forms first, so the later checks
  // test the analysis and not the generator: RK4 at 25 us and a 60-step
  // bisection give impact times to ~1e-12 s; quarter_period is exact to ~1e-12.
  const double theta0 = 0.5 * kBlock.alpha();
  const auto rocking = test::free_rocking(kBlock.p(), kBlock.alpha(), kBlock.e(), theta0, kSampleStep, 4.0);
  const std::vector<double> times = housner_impact_times(kBlock, theta0, 8);
  ASSERT_GE(rocking.impact_times.size(), 8u);
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(rocking.impact_times[k], times[k], 1e-9);
}

TEST(MotionAnalysis, HousnerFreeRockingWithoutNoise) {
  const double theta0 = 0.5 * kBlock.alpha();
  const auto rocking = test::free_rocking(kBlock.p(), kBlock.alpha(), kBlock.e(), theta0, kSampleStep, 4.0);
  AnalysisParameters parameters;
  parameters.angle_noise = parameters.length_noise = 1e-6;  // resolution of a noise-free signal
  const BodyMotion motion = rocking_motion(rocking, kBlock, 0.0, 1);
  const MotionSummary summary = analyse_motion(motion, geometry_of(kBlock), parameters);
  expect_housner(summary.impacts[0], kBlock, theta0, 0.0, parameters, 8);
  EXPECT_NEAR(summary.impacts[0].median_ratio, kBlock.e(), 0.2 * std::pow(kBlock.p() * parameters.impact_window, 2));
  EXPECT_TRUE(summary.impacts[1].impacts.empty());  // rock_y is identically 0
  EXPECT_FALSE(summary.overturn.overturned);
  // Peaks: the release angle at t = 0, and the first negative amplitude.
  EXPECT_DOUBLE_EQ(summary.peaks[kRockX].max, theta0);
  EXPECT_DOUBLE_EQ(summary.peaks[kRockX].t_max, 0.0);
  // A sample, not the vertex: within half a step of the peak, where theta'' <= p^2 sin(alpha).
  const double sample_tolerance = kBlock.p() * kBlock.p() * std::sin(kBlock.alpha()) * std::pow(kSampleStep / 2, 2) / 2;
  EXPECT_NEAR(-summary.peaks[kRockX].min, reference::amplitude_map(kBlock, theta0, 1)[0], sample_tolerance);
  // Rocking explains both slide and uplift: the body only rocks (and rests at the very end).
  for (const ModeSegment& segment : summary.modes)
    EXPECT_TRUE(segment.mode == Mode::rock || segment.mode == Mode::rest)
        << mode_name(segment.mode) << " at " << segment.start;
  EXPECT_EQ(summary.modes.front().mode, Mode::rock);
  EXPECT_TRUE(summary.slips.empty());
  EXPECT_TRUE(summary.separations.empty());
}

TEST(MotionAnalysis, HousnerFreeRockingWithSensorNoise) {
  const double theta0 = 0.6 * kBlock.alpha(), noise = 5e-4;  // the format example's sensor_noise
  const auto rocking = test::free_rocking(kBlock.p(), kBlock.alpha(), kBlock.e(), theta0, kSampleStep, 4.0);
  AnalysisParameters parameters;
  parameters.angle_noise = parameters.length_noise = noise;
  const BodyMotion motion = rocking_motion(rocking, kBlock, noise, 7);
  const MotionSummary summary = analyse_motion(motion, geometry_of(kBlock), parameters);
  expect_housner(summary.impacts[0], kBlock, theta0, noise, parameters, 5);
  for (const ModeSegment& segment : summary.modes)
    if (segment.end < rocking.impact_times[4]) EXPECT_EQ(segment.mode, Mode::rock) << segment.start;
}

TEST(MotionAnalysis, LostSamplesAwayFromImpactsChangeNothingBeyondTolerance) {
  const double theta0 = 0.5 * kBlock.alpha();
  const auto rocking = test::free_rocking(kBlock.p(), kBlock.alpha(), kBlock.e(), theta0, kSampleStep, 4.0);
  AnalysisParameters parameters;
  parameters.angle_noise = parameters.length_noise = 1e-6;
  BodyMotion motion = rocking_motion(rocking, kBlock, 0.0, 1);
  // Lose 3 samples (15 ms) every 0.2 s, from 0.1 s on, unless within 0.06 s of an impact
  // (beyond the 0.05 s fit window) and a block of 8 samples at 2.0 s.
  int lost = 0;
  for (std::size_t i = 0; i < motion.time.size(); ++i) {
    bool near_impact = false;
    for (double t : rocking.impact_times) near_impact = near_impact || std::fabs(motion.time[i] - t) < 0.06;
    const bool periodic = i % 40 >= 20 && i % 40 < 23 && !near_impact;  // keeps the release sample
    const bool block = motion.time[i] >= 2.0 && motion.time[i] < 2.04 && !near_impact;
    if (!periodic && !block) continue;
    for (auto& channel : motion.channels) channel[i] = NAN;
    ++lost;
  }
  ASSERT_GT(lost, 30);
  const MotionSummary summary = analyse_motion(motion, geometry_of(kBlock), parameters);
  expect_housner(summary.impacts[0], kBlock, theta0, 0.0, parameters, 8, 16 * kSampleStep);
  for (const ModeSegment& segment : summary.modes) EXPECT_NE(segment.mode, Mode::slide);
}

// Newmark's block on a sine base: a_g = A sin(w t). Starting from rest it
// slips when A sin(w t0) = mu g, toward -x, with u'' = -A sin(w t) + mu g,
// u' = (A / w)(cos w t - cos w t0) + mu g (t - t0), until u' = 0 at t1.
// Every half period repeats the first event mirrored (a_g is antisymmetric
// and each event starts from rest) as long as t1 < t0 + T / 2. With these
// numbers: t0 = 0.152 s, t1 = 0.449 s, 0.20 s of rest, 11.8 mm per event.
struct SineSlip {
  double A = 3.0, w = 2 * M_PI, mu = 0.25, g = 9.81;
  double half_period() const { return M_PI / w; }
  double t0() const { return std::asin(mu * g / A) / w; }
  double velocity(double t) const { return A / w * (std::cos(w * t) - std::cos(w * t0())) + mu * g * (t - t0()); }
  double t1() const {  // u' < 0 just after t0; bisect its return to zero
    double lo = t0() + 1e-6, hi = t0() + M_PI / w;
    for (int it = 0; it < 80; ++it) (velocity(0.5 * (lo + hi)) < 0 ? lo : hi) = 0.5 * (lo + hi);
    return hi;
  }
  double slip() const {  // integral of u' from t0 to t1
    const double a = t0(), b = t1();
    return A / (w * w) * (std::sin(w * b) - std::sin(w * a)) - A / w * std::cos(w * a) * (b - a) +
           0.5 * mu * g * (b - a) * (b - a);
  }
};

BodyMotion sliding_motion(const SineSlip& s, double duration) {
  const auto history = reference::newmark_sliding([&](double t) { return s.A * std::sin(s.w * t); }, s.mu, s.mu, s.g,
                                                  duration, kSampleStep, 1e-6);
  BodyMotion motion;
  motion.time = history.t;
  motion.channels[kSlideX] = history.u;
  return motion;
}

// Detection lags the true onset and stop: the fitted speed must exceed
// v = 4 sd(slope); at onset u' grows as j (t - t0)^2 / 2 with jerk
// j = A w cos(w t0), reached after sqrt(2 v / j); at the stop it falls at the
// deceleration a1 = |mu g - A sin(w t1)|, reached v / a1 before. The fit
// window (+-W) smears either by up to W, and the sampling by one step.
TEST(MotionAnalysis, NewmarkSlipOnsetsStopsAndSlip) {
  const SineSlip s;
  const double duration = 3.1;
  const BodyMotion motion = sliding_motion(s, duration);
  AnalysisParameters parameters;
  parameters.length_noise = 1e-6;
  const MotionSummary summary = analyse_motion(motion, {}, parameters);

  const double sd = signal::local_rates(motion.time, motion.channels[kSlideX], parameters.rate_half_window,
                                        parameters.length_noise).sd[100];
  const double v = parameters.threshold_sigmas * sd, W = parameters.rate_half_window;
  const double jerk = s.A * s.w * std::cos(s.w * s.t0());
  const double deceleration = std::fabs(s.mu * s.g - s.A * std::sin(s.w * s.t1()));
  const double onset_tolerance = std::sqrt(2 * v / jerk) + W + kSampleStep;
  const double stop_tolerance = v / deceleration + W + kSampleStep;
  // Slip missed at either end: at most the speed there times the lag.
  const double slip_tolerance = 0.5 * jerk * std::pow(onset_tolerance, 3) + deceleration * std::pow(stop_tolerance, 2);

  // Rest between events longer than the chatter suppression and both fit windows.
  ASSERT_GT(s.t0() + s.half_period() - s.t1(), parameters.min_segment + 2 * W);
  int events = 0;  // half periods whose event starts inside the record
  while (s.t0() + s.half_period() * events < duration) ++events;
  // ... and ends, followed by a rest longer than the chatter suppression.
  ASSERT_LT(s.t1() + s.half_period() * (events - 1) + stop_tolerance + parameters.min_segment, duration);
  ASSERT_EQ(summary.slips.size(), static_cast<std::size_t>(events));
  for (int k = 0; k < events; ++k) {
    const SlipEvent& event = summary.slips[k];
    EXPECT_NEAR(event.onset, s.t0() + s.half_period() * k, onset_tolerance) << k;
    EXPECT_NEAR(event.stop, s.t1() + s.half_period() * k, stop_tolerance) << k;
    EXPECT_NEAR(event.slip_x, (k % 2 ? -1 : 1) * s.slip(), slip_tolerance) << k;
    EXPECT_EQ(event.slip_y, 0.0);
  }
  for (const ModeSegment& segment : summary.modes)
    EXPECT_TRUE(segment.mode == Mode::slide || segment.mode == Mode::rest) << mode_name(segment.mode);
}

// tilt() inverts the format's rock_x, rock_y (rocking_angles() of the kernel)
// for any orientation, upright or upside down.
TEST(MotionAnalysis, TiltInvertsTheRockingAnglesKernel) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d e3 = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Vector2d rock = rocking_angles(e3);
    EXPECT_NEAR(tilt(rock.x(), rock.y()), std::acos(e3.z()), 1e-9) << e3.transpose();
  }
}

// Exact rates against central differences of the kernel's channels along a
// smooth motion: the O(dt^2) difference error at dt = 1e-5 s is ~1e-9 of the rates.
TEST(MotionAnalysis, ChannelRatesMatchDifferencesOfTheKernelChannels) {
  const Eigen::Vector3d com_in_body(0.02, -0.01, 0.4);
  const BodyFrameGeometry geometry{com_in_body, 0.8};
  auto pose_at = [&](double t) {
    const Eigen::Quaterniond q = Eigen::AngleAxisd(0.3 * std::sin(2 * t), Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(0.2 * std::sin(3 * t), Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(0.1 * t, Eigen::Vector3d::UnitX());
    return BodyPose{Eigen::Vector3d(0.1 * t * t, std::sin(t), 0.4 + 0.01 * t) + q * com_in_body, q};
  };
  auto support_at = [](double t) { return Eigen::Vector3d(0.05 * std::sin(5 * t), 0, 0); };
  auto channels_at = [&](double t0, double t) {
    ModeChannelTracker tracker;
    tracker.update(pose_at(t0), geometry, support_at(t0));
    return tracker.update(pose_at(t), geometry, support_at(t));
  };
  const double dt = 1e-5;
  for (double t : {0.3, 1.1, 2.0}) {
    const ModeChannels plus = channels_at(0, t + dt), minus = channels_at(0, t - dt);
    const BodyPose pose = pose_at(t);
    const Eigen::Quaterniond q1 = pose_at(t + dt).orientation, q0 = pose_at(t - dt).orientation;
    const Eigen::AngleAxisd delta(q1 * q0.inverse());
    const Eigen::Vector3d omega = delta.axis() * delta.angle() / (2 * dt);
    const Eigen::Vector3d velocity = (pose_at(t + dt).com - pose_at(t - dt).com) / (2 * dt);
    const Eigen::Vector3d support_velocity = (support_at(t + dt) - support_at(t - dt)) / (2 * dt);
    const ChannelSeries rates = channel_rates({pose.orientation}, {omega}, {velocity}, {support_velocity}, com_in_body);
    const double expected[] = {plus.rock_x - minus.rock_x, plus.rock_y - minus.rock_y, plus.twist - minus.twist,
                               plus.slide_x - minus.slide_x, plus.slide_y - minus.slide_y, plus.uplift - minus.uplift};
    for (int c = 0; c < kChannelCount; ++c) EXPECT_NEAR(rates[c][0], expected[c] / (2 * dt), 1e-6) << c << " at " << t;
  }
}

// Released beyond alpha the block falls: overturning is flagged at the first
// sample beyond alpha + margin (the rate test passes there: the fall
// accelerates), and not for a release just inside alpha.
TEST(MotionAnalysis, OverturningBeyondSlendernessAndLyingOnASide) {
  AnalysisParameters parameters;
  parameters.angle_noise = 1e-6;
  const BodyGeometry geometry = geometry_of(kBlock);
  // Release beyond alpha: theta grows; simulate with r = 1 (no impact happens).
  const auto falling = test::free_rocking(kBlock.p(), kBlock.alpha(), 1.0, kBlock.alpha() + 0.01, kSampleStep, 1.5);
  BodyMotion motion;
  motion.time = falling.t;
  motion.channels[kRockX] = falling.theta;
  const Overturn overturn = analyse_motion(motion, geometry, parameters).overturn;
  ASSERT_TRUE(overturn.overturned);
  std::size_t first = 0;
  while (falling.theta[first] <= kBlock.alpha() + parameters.overturn_margin) ++first;
  EXPECT_DOUBLE_EQ(overturn.time, falling.t[first]);
  EXPECT_EQ(overturn.criterion, "rock_x beyond alpha + margin and growing");

  const auto rocking = test::free_rocking(kBlock.p(), kBlock.alpha(), kBlock.e(), kBlock.alpha() - 0.01, kSampleStep, 3.0);
  motion.time = rocking.t;
  motion.channels[kRockX] = rocking.theta;
  EXPECT_FALSE(analyse_motion(motion, geometry, parameters).overturn.overturned);

  // A body on its side (rock_y = -pi/2 from 1 s on), geometry unknown.
  for (std::size_t i = 0; i < motion.time.size(); ++i) {
    motion.channels[kRockX][i] = 0;
    motion.channels[kRockY].push_back(motion.time[i] < 1.0 ? 0.0 : -M_PI / 2);
  }
  const MotionSummary summary = analyse_motion(motion, {}, parameters);
  EXPECT_EQ(summary.overturn.criterion, "lying on a side");
  EXPECT_DOUBLE_EQ(summary.overturn.time, 1.0);
  EXPECT_EQ(summary.modes.back().mode, Mode::overturned);
  EXPECT_NEAR(summary.residual.mean[kRockY], -M_PI / 2, 1e-15);
}

// A body thrown up: uplift beyond what its (zero) rocking explains is flight;
// the separation spans the samples above the threshold 4 sqrt(sd_L^2 + (b sd_angle)^2).
TEST(MotionAnalysis, FlightAndSeparationFromUpliftBeyondRocking) {
  AnalysisParameters parameters;
  parameters.angle_noise = parameters.length_noise = 1e-4;
  BodyMotion motion;
  const double g = 9.81, v0 = 0.5, start = 0.5;  // ballistic hop: up 12.7 mm for 0.102 s
  for (double t = 0; t < 1.5; t += kSampleStep) {
    motion.time.push_back(t);
    const double s = t - start;
    motion.channels[kUplift].push_back(s > 0 && s < 2 * v0 / g ? v0 * s - 0.5 * g * s * s : 0.0);
    motion.channels[kRockX].push_back(0.0);
  }
  const MotionSummary summary = analyse_motion(motion, geometry_of(kBlock), parameters);
  ASSERT_EQ(summary.separations.size(), 1u);
  const double threshold = 4 * std::hypot(1e-4, std::hypot(0.1, 0.1) * 1e-4);
  // Times where the parabola crosses the threshold, up to one sample.
  const double rise = (v0 - std::sqrt(v0 * v0 - 2 * g * threshold)) / g;
  EXPECT_NEAR(summary.separations[0].start, start + rise, kSampleStep);
  EXPECT_NEAR(summary.separations[0].end, start + 2 * v0 / g - rise, kSampleStep);
  EXPECT_NEAR(summary.separations[0].peak_gap, v0 * v0 / (2 * g), g * kSampleStep * kSampleStep / 8);
  bool flight = false;
  for (const ModeSegment& segment : summary.modes) flight = flight || segment.mode == Mode::flight;
  EXPECT_TRUE(flight);
}

TEST(MotionAnalysis, BadInputNamesTheProblem) {
  BodyMotion motion;
  motion.time = {0, 0.1, 0.2, 0.3};
  motion.channels[kRockX] = {0, 0, 0};
  try {
    analyse_motion(motion, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("channel 0 has 3 samples, time has 4"), std::string::npos) << e.what();
  }
  motion.channels[kRockX].push_back(0);
  AnalysisParameters parameters;
  parameters.angle_noise = 0;
  EXPECT_THROW(analyse_motion(motion, {}, parameters), InputError);
}

}  // namespace
}  // namespace freestand::analysis
