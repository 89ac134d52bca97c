#include "comparison.h"

#include <unsupported/Eigen/FFT>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>

#include "freestand/input_error.h"

namespace freestand::comparison {

namespace {

double peak_magnitude(const std::vector<double>& y) {
  double peak = 0;
  for (double v : y) peak = std::max(peak, std::fabs(v));
  return peak;
}

double rms_difference(const Aligned& a, std::size_t first, std::size_t last) {
  double sum = 0;
  for (std::size_t i = first; i < last; ++i) sum += std::pow(a.simulated[i] - a.recorded[i], 2);
  return std::sqrt(sum / static_cast<double>(last - first));
}

// Vertex offset (in steps, within [-0.5, 0.5] for a true maximum) of the
// parabola through (-1, left), (0, centre), (1, right).
double parabola_vertex(double left, double centre, double right) {
  const double curvature = left - 2 * centre + right;
  return curvature < 0 ? 0.5 * (left - right) / curvature : 0.0;
}

// Pearson correlation of r[k] with s[k - lag] over the overlap (finite pairs).
double lagged_correlation(const std::vector<double>& r, const std::vector<double>& s, long lag) {
  double sr = 0, ss = 0, srr = 0, sss = 0, srs = 0;
  long count = 0;
  for (long k = std::max(0L, lag); k < static_cast<long>(r.size()) && k - lag < static_cast<long>(s.size()); ++k) {
    const double a = r[k], b = s[k - lag];
    if (!std::isfinite(a) || !std::isfinite(b)) continue;
    sr += a, ss += b, srr += a * a, sss += b * b, srs += a * b;
    ++count;
  }
  const double cov = srs - sr * ss / count, var_r = srr - sr * sr / count, var_s = sss - ss * ss / count;
  return cov / std::sqrt(var_r * var_s);
}

// Both series on one uniform grid (the recording's median step) over the
// interval where both have finite samples. The recording is NaN inside its
// gaps (compared samples more than 1.5 steps apart): a line bridging a lost
// stretch of rocking would pull the correlation's peak.
struct UniformPair {
  double t0 = 0, dt = 0;
  std::vector<double> recorded, simulated;
};
UniformPair uniform_pair(const Aligned& a, const std::vector<double>& simulated_time,
                         const std::vector<double>& simulated) {
  UniformPair pair;
  pair.dt = signal::median_step(a.time);
  pair.t0 = a.time.front();
  const std::size_t n = static_cast<std::size_t>(std::floor((a.time.back() - pair.t0) / pair.dt)) + 1;
  pair.recorded = signal::resample_uniform(a.time, a.recorded, pair.t0, pair.dt, n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto after = std::upper_bound(a.time.begin(), a.time.end(), pair.t0 + k * pair.dt);
    if (after != a.time.begin() && after != a.time.end() && *after - *(after - 1) > 1.5 * pair.dt)
      pair.recorded[k] = kNaN;
  }
  pair.simulated = signal::resample_uniform(simulated_time, simulated, pair.t0, pair.dt, n);
  return pair;
}

// Least squares recorded = gain * shifted + bias.
void fit_gain(const std::vector<double>& recorded, const std::vector<double>& shifted, double noise,
              OffsetGain& out) {
  double ms = 0, mr = 0;
  int n = 0;
  for (std::size_t i = 0; i < recorded.size(); ++i)
    if (std::isfinite(shifted[i])) ms += shifted[i], mr += recorded[i], ++n;
  ms /= n;
  mr /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < recorded.size(); ++i)
    if (std::isfinite(shifted[i])) {
      sxx += (shifted[i] - ms) * (shifted[i] - ms);
      sxy += (shifted[i] - ms) * (recorded[i] - mr);
    }
  if (!(sxx > 0)) return;  // constant simulation: no gain
  out.gain = sxy / sxx;
  out.gain_sd = noise / std::sqrt(sxx);
  out.bias = mr - out.gain * ms;
}

ImpactDecay impact_decay(const analysis::RockingImpacts& recorded, const analysis::RockingImpacts& simulated) {
  ImpactDecay decay;
  for (const auto& impact : recorded.impacts) decay.recorded_ratios.push_back(impact.ratio);
  for (const auto& impact : simulated.impacts) decay.simulated_ratios.push_back(impact.ratio);
  for (const auto& cycle : recorded.half_cycles) decay.recorded_amplitudes.push_back(cycle.amplitude);
  for (const auto& cycle : simulated.half_cycles) decay.simulated_amplitudes.push_back(cycle.amplitude);
  decay.recorded_median = recorded.median_ratio;
  decay.simulated_median = simulated.median_ratio;
  return decay;
}

}  // namespace

Aligned align(const std::vector<double>& recorded_time, const std::vector<double>& recorded,
              const std::vector<double>& simulated_time, const std::vector<double>& simulated) {
  if (recorded_time.size() != recorded.size() || simulated_time.size() != simulated.size())
    throw InputError(fmt::format("comparison: recording has {} times and {} values, simulation {} and {}",
                                 recorded_time.size(), recorded.size(), simulated_time.size(), simulated.size()));
  for (const auto* t : {&recorded_time, &simulated_time})
    for (std::size_t i = 1; i < t->size(); ++i)
      if (!((*t)[i] > (*t)[i - 1]))
        throw InputError(fmt::format("comparison: {} time not strictly increasing at sample {}",
                                     t == &recorded_time ? "recording" : "simulation", i));
  Aligned a;
  for (std::size_t i = 0; i < recorded_time.size(); ++i) {
    const double s = signal::interpolate(simulated_time, simulated, recorded_time[i]);
    if (!std::isfinite(recorded[i]) || !std::isfinite(s)) continue;
    a.time.push_back(recorded_time[i]);
    a.recorded.push_back(recorded[i]);
    a.simulated.push_back(s);
  }
  return a;
}

Spectrum spectrum(const std::vector<double>& t, const std::vector<double>& y) {
  Spectrum out;
  if (t.size() < 8 || t.size() != y.size()) return out;
  const double dt = signal::median_step(t);
  const std::size_t n = static_cast<std::size_t>(std::floor((t.back() - t.front()) / dt)) + 1;
  std::vector<double> u = signal::resample_uniform(t, y, t.front(), dt, n);
  u.erase(std::remove_if(u.begin(), u.end(), [](double v) { return !std::isfinite(v); }), u.end());
  if (u.size() < 8) return out;
  const double mean = std::accumulate(u.begin(), u.end(), 0.0) / u.size();
  for (std::size_t k = 0; k < u.size(); ++k)  // Hann window
    u[k] = (u[k] - mean) * 0.5 * (1 - std::cos(2 * M_PI * k / (u.size() - 1)));
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> transform;
  fft.fwd(transform, u);
  const std::size_t bins = u.size() / 2 + 1;
  const double bin_width = 1.0 / (u.size() * dt);
  std::vector<double> power(bins);
  double total = 0, weighted = 0;
  std::size_t best = 1;
  for (std::size_t k = 1; k < bins; ++k) {
    power[k] = std::norm(transform[k]);
    total += power[k];
    weighted += k * bin_width * power[k];
    if (power[k] > power[best]) best = k;
  }
  if (!(total > 0)) return out;
  out.centroid = weighted / total;
  double shift = 0;  // Gaussian (log-parabola) interpolation of the peak
  if (best + 1 < bins && power[best - 1] > 0 && power[best + 1] > 0)
    shift = parabola_vertex(std::log(power[best - 1]), std::log(power[best]), std::log(power[best + 1]));
  out.dominant_frequency = (best + shift) * bin_width;
  return out;
}

OffsetGain offset_and_gain(const Aligned& a, const std::vector<double>& simulated_time,
                           const std::vector<double>& simulated, const ComparisonParameters& p) {
  OffsetGain out;
  if (a.time.size() < 8) return out;
  const UniformPair pair = uniform_pair(a, simulated_time, simulated);
  const long max_lag = std::lround(p.max_lag / pair.dt);
  std::vector<double> correlation(2 * max_lag + 1, -2);
  long best = 0;
  for (long lag = -max_lag; lag <= max_lag; ++lag) {
    const double c = lagged_correlation(pair.recorded, pair.simulated, lag);
    correlation[lag + max_lag] = std::isfinite(c) ? c : -2;
    if (correlation[lag + max_lag] > correlation[best + max_lag]) best = lag;
  }
  double shift = 0;
  if (std::abs(best) < max_lag)
    shift = parabola_vertex(correlation[best + max_lag - 1], correlation[best + max_lag],
                            correlation[best + max_lag + 1]);
  out.offset = (best + shift) * pair.dt;
  out.correlation = correlation[best + max_lag] >= -1 ? correlation[best + max_lag] : kNaN;
  std::vector<double> shifted(a.time.size());
  for (std::size_t i = 0; i < a.time.size(); ++i)
    shifted[i] = signal::interpolate(simulated_time, simulated, a.time[i] - out.offset);
  fit_gain(a.recorded, shifted, p.noise, out);
  return out;
}

ChannelComparison compare_channel(const std::vector<double>& recorded_time, const std::vector<double>& recorded,
                                  const std::vector<double>& simulated_time, const std::vector<double>& simulated,
                                  const ComparisonParameters& p) {
  const Aligned a = align(recorded_time, recorded, simulated_time, simulated);
  ChannelComparison out;
  out.samples = static_cast<int>(a.time.size());
  if (out.samples < 3) return out;
  out.peak_recorded = peak_magnitude(a.recorded);
  out.peak_simulated = peak_magnitude(a.simulated);
  out.peak_error_percent = 100 * (out.peak_simulated - out.peak_recorded) / out.peak_recorded;

  const double end = a.time.back(), start = end - p.residual_fraction * (end - a.time.front());
  const signal::IndexRange tail = signal::index_range(a.time, start, end);
  out.residual_recorded = signal::finite_mean(a.recorded, tail);
  out.residual_simulated = signal::finite_mean(a.simulated, tail);
  out.residual_difference = out.residual_simulated - out.residual_recorded;

  out.spectrum_recorded = spectrum(a.time, a.recorded);
  out.spectrum_simulated = spectrum(a.time, a.simulated);
  out.nrmse = rms_difference(a, 0, a.time.size()) / out.peak_recorded;

  out.divergence_threshold = std::max(p.threshold_sigmas * p.noise, p.divergence_fraction * out.peak_recorded);
  std::size_t first = 0;
  for (std::size_t i = 0; i < a.time.size(); ++i) {
    while (a.time[first] < a.time[i] - p.divergence_window) ++first;
    if (a.time[i] - a.time.front() < p.divergence_window) continue;  // window not yet full
    if (rms_difference(a, first, i + 1) > out.divergence_threshold) {
      out.divergence_time = a.time[i];
      break;
    }
  }
  out.offset_gain = offset_and_gain(a, simulated_time, simulated, p);
  return out;
}

BodyComparison compare_body(const analysis::BodyMotion& recorded, const analysis::BodyMotion& simulated,
                            const analysis::BodyGeometry& geometry, const analysis::AnalysisParameters& parameters,
                            ComparisonParameters comparison) {
  analysis::check_motion(recorded, parameters);
  analysis::check_motion(simulated, parameters);
  BodyComparison out;
  for (int c = 0; c < analysis::kChannelCount; ++c) {
    if (recorded.channels[c].empty() || simulated.channels[c].empty()) continue;
    const bool angle = c == analysis::kRockX || c == analysis::kRockY || c == analysis::kTwist;
    comparison.noise = angle ? parameters.angle_noise : parameters.length_noise;
    out.channels[c] = compare_channel(recorded.time, recorded.channels[c], simulated.time, simulated.channels[c],
                                      comparison);
  }
  for (int axis = 0; axis < 2; ++axis)
    out.decay[axis] = impact_decay(analysis::rocking_impacts(recorded, axis, geometry, parameters),
                                   analysis::rocking_impacts(simulated, axis, geometry, parameters));
  return out;
}

}  // namespace freestand::comparison
