#include "signal_tools.h"

#include <Eigen/Dense>
#include <boost/math/distributions/gamma.hpp>
#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <utility>

namespace freestand::signal {

IndexRange index_range(const std::vector<double>& t, double lo, double hi) {
  const auto first = std::lower_bound(t.begin(), t.end(), lo);
  const auto last = std::upper_bound(first, t.end(), hi);
  return {static_cast<std::size_t>(first - t.begin()), static_cast<std::size_t>(last - t.begin())};
}

LocalFit local_fit(const std::vector<double>& t, const std::vector<double>& y, IndexRange range,
                   double t_eval, int degree, double noise) {
  // Powers of u = (t - t_eval) / scale: scaling keeps the normal equations
  // well conditioned whatever the window length.
  double scale = 0;
  for (std::size_t i = range.first; i < range.last; ++i)
    if (std::isfinite(y[i])) scale = std::max(scale, std::fabs(t[i] - t_eval));
  const int terms = degree + 1;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  LocalFit fit;
  for (std::size_t i = range.first; i < range.last; ++i) {
    if (!std::isfinite(y[i])) continue;
    const double u = (t[i] - t_eval) / scale;
    const Eigen::Vector3d row(1.0, u, u * u);
    normal.topLeftCorner(terms, terms) += row.head(terms) * row.head(terms).transpose();
    rhs.head(terms) += row.head(terms) * y[i];
    ++fit.samples;
  }
  if (fit.samples < degree + 2 || scale == 0) return fit;
  const Eigen::MatrixXd inverse = normal.topLeftCorner(terms, terms).inverse();
  if (!inverse.allFinite()) return fit;  // samples at fewer than degree + 1 distinct times
  const Eigen::VectorXd beta = inverse * rhs.head(terms);
  fit.valid = true;
  fit.value = beta(0);
  fit.slope = beta(1) / scale;
  fit.slope_sd = noise * std::sqrt(inverse(1, 1)) / scale;
  if (degree == 2) fit.curvature = 2 * beta(2) / (scale * scale);
  return fit;
}

Rates local_rates(const std::vector<double>& t, const std::vector<double>& y, double half_window,
                  double noise) {
  Rates rates{std::vector<double>(t.size(), kNaN), std::vector<double>(t.size(), kNaN)};
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(y[i])) continue;
    const LocalFit fit = local_fit(t, y, index_range(t, t[i] - half_window, t[i] + half_window),
                                   t[i], 1, noise);
    if (!fit.valid) continue;
    rates.value[i] = fit.slope;
    rates.sd[i] = fit.slope_sd;
  }
  return rates;
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xi) {
  if (x.empty() || !(xi >= x.front() && xi <= x.back())) return kNaN;
  const std::size_t hi = std::lower_bound(x.begin(), x.end(), xi) - x.begin();
  if (x[hi] == xi) return y[hi];
  const double f = (xi - x[hi - 1]) / (x[hi] - x[hi - 1]);
  return y[hi - 1] + f * (y[hi] - y[hi - 1]);  // NaN when either neighbour is lost
}

namespace {

// The finite samples of y, with their times.
std::pair<std::vector<double>, std::vector<double>> finite_samples(const std::vector<double>& t,
                                                                   const std::vector<double>& y) {
  std::pair<std::vector<double>, std::vector<double>> out;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::isfinite(y[i])) out.first.push_back(t[i]), out.second.push_back(y[i]);
  return out;
}

}  // namespace

std::vector<double> resample_uniform(const std::vector<double>& t, const std::vector<double>& y,
                                     double t0, double dt, std::size_t n) {
  const auto [valid_t, valid_y] = finite_samples(t, y);
  std::vector<double> out(n);
  for (std::size_t k = 0; k < n; ++k) out[k] = interpolate(valid_t, valid_y, t0 + k * dt);
  return out;
}

std::vector<double> bridge_lost(const std::vector<double>& t, const std::vector<double>& y) {
  const auto [valid_t, valid_y] = finite_samples(t, y);
  std::vector<double> out(y.size(), kNaN);
  if (valid_t.empty()) return out;
  for (std::size_t i = 0; i < y.size(); ++i)
    out[i] = std::isfinite(y[i]) ? y[i] : interpolate(valid_t, valid_y, std::clamp(t[i], valid_t.front(), valid_t.back()));
  return out;
}

LostSamples lost_samples(const std::vector<double>& t, const std::vector<double>& y) {
  LostSamples out;
  for (std::size_t i = 0; i < y.size();) {
    if (std::isfinite(y[i])) { ++i; continue; }
    std::size_t end = i;
    while (end < y.size() && !std::isfinite(y[end])) ++end;
    const double span = t[std::min(end, y.size() - 1)] - t[i == 0 ? 0 : i - 1];
    if (span > out.longest) out.longest = span, out.longest_at = t[i];
    out.count += end - i, i = end;
  }
  return out;
}

double second_difference_noise(const std::vector<double>& y) {
  std::vector<double> d;
  for (std::size_t k = 1; k + 1 < y.size(); ++k)
    if (const double v = y[k + 1] - 2 * y[k] + y[k - 1]; std::isfinite(v)) d.push_back(std::abs(v));
  if (d.size() < 3) return kNaN;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return 1.4826 * d[d.size() / 2] / std::sqrt(6.0);  // 1.4826 MAD: the s.d. of a Gaussian
}

double median_step(const std::vector<double>& t) {
  if (t.size() < 2) return kNaN;
  std::vector<double> steps(t.size() - 1);
  for (std::size_t i = 0; i + 1 < t.size(); ++i) steps[i] = t[i + 1] - t[i];
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return steps[steps.size() / 2];
}

namespace {

// y less the line through its end points (so its periodic extension has no jump, and a line
// has no acceleration), and the DFT of the rest.
struct Detrended {
  std::vector<double> line;
  std::vector<std::complex<double>> spectrum;
};
Detrended detrended(const std::vector<double>& y) {
  const std::size_t n = y.size();
  Detrended out{std::vector<double>(n), {}};
  std::vector<double> rest(n);
  for (std::size_t k = 0; k < n; ++k) {
    out.line[k] = y.front() + (y.back() - y.front()) * k / (n - 1.0);
    rest[k] = y[k] - out.line[k];
  }
  Eigen::FFT<double>().fwd(out.spectrum, rest);
  return out;
}

}  // namespace

std::vector<double> band_limited(const std::vector<double>& y, double dt, const std::function<bool(double)>& keep) {
  const std::size_t n = y.size();
  if (n < 3) return y;
  Detrended parts = detrended(y);
  for (std::size_t k = 1; 2 * k <= n; ++k)
    if (!keep(k / (n * dt))) parts.spectrum[k] = parts.spectrum[n - k] = 0;
  std::vector<double> out;
  Eigen::FFT<double>().inv(out, parts.spectrum);
  for (std::size_t k = 0; k < n; ++k) out[k] += parts.line[k];
  return out;
}

NoiseCut cut_noise(const std::vector<double>& y, double dt, double noise) {
  const std::size_t n = y.size();
  if (n < 8 || !(noise > 0)) return {y, 0.5 / dt};
  const Detrended parts = detrended(y);
  // Averaged over 1 Hz (n dt bins), at least 5, mirrored at 0 and Nyquist: one bin's power
  // scatters by 100 %, an average over w bins as Gamma(w, 1 / w) times its mean.
  const long last = static_cast<long>(n / 2), half = std::max(2L, std::lround(0.5 * n * dt)), w = 2 * half + 1;
  const auto power = [&](long k) {
    k = std::abs(k);
    return std::norm(parts.spectrum[std::clamp(k > last ? 2 * last - k : k, 0L, last)]);
  };
  // Kept where signal exceeds noise (twice the noise's power), and beyond what noise alone
  // reaches in any bin but with probability 1 % (Bonferroni over the bins): one stray bin of
  // noise kept at 80 Hz would add 4 m/s^2 rms to an acceleration.
  const double chance = boost::math::quantile(boost::math::complement(
                            boost::math::gamma_distribution<double>(w, 1.0 / w), 0.01 / last)),
               threshold = std::max(2.0, chance) * n * noise * noise;  // E |DFT of the noise|^2 = n noise^2
  std::vector<bool> kept(last + 1);
  double highest = 0;
  for (long k = 1; k <= last; ++k) {
    double sum = 0;
    for (long j = k - half; j <= k + half; ++j) sum += power(j);
    if ((kept[k] = sum / w > threshold)) highest = k / (n * dt);
  }
  return {band_limited(y, dt, [&](double hz) { return kept[std::lround(hz * n * dt)]; }), highest};
}

double finite_mean(const std::vector<double>& y, IndexRange range) {
  double sum = 0;
  int count = 0;
  for (std::size_t i = range.first; i < range.last; ++i)
    if (std::isfinite(y[i])) {
      sum += y[i];
      ++count;
    }
  return count ? sum / count : kNaN;
}

double sample_sd(const std::vector<double>& x) {
  if (x.size() < 2) return kNaN;
  const Eigen::Map<const Eigen::ArrayXd> a(x.data(), static_cast<Eigen::Index>(x.size()));
  return std::sqrt((a - a.mean()).square().sum() / static_cast<double>(x.size() - 1));
}

std::vector<Run> label_runs(const std::vector<int>& labels) {
  std::vector<Run> runs;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (runs.empty() || runs.back().label != labels[i])
      runs.push_back({labels[i], i, i});
    else
      runs.back().last = i;
  }
  return runs;
}

double run_duration(const std::vector<double>& t, const std::vector<Run>& runs, std::size_t i) {
  const double end = i + 1 < runs.size() ? t[runs[i + 1].first] : t.back();
  return end - t[runs[i].first];
}

namespace {

// Joins neighbouring runs that carry the same label.
std::vector<Run> join_equal(const std::vector<Run>& runs) {
  std::vector<Run> joined;
  for (const Run& run : runs) {
    if (!joined.empty() && joined.back().label == run.label)
      joined.back().last = run.last;
    else
      joined.push_back(run);
  }
  return joined;
}

}  // namespace

std::vector<Run> merge_short_runs(std::vector<Run> runs, const std::vector<double>& t,
                                  double min_duration) {
  while (runs.size() > 1) {
    std::size_t shortest = 0;
    for (std::size_t i = 1; i < runs.size(); ++i)
      if (run_duration(t, runs, i) < run_duration(t, runs, shortest)) shortest = i;
    if (run_duration(t, runs, shortest) >= min_duration) break;
    const bool has_left = shortest > 0, has_right = shortest + 1 < runs.size();
    const bool take_left =
        has_left && (!has_right || run_duration(t, runs, shortest - 1) >= run_duration(t, runs, shortest + 1));
    runs[shortest].label = runs[take_left ? shortest - 1 : shortest + 1].label;
    runs = join_equal(runs);
  }
  return runs;
}

}  // namespace freestand::signal
