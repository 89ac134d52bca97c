#include "freestand/table_motion.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "freestand/input_error.h"

namespace freestand {

AxisState AxisMotion::at(double t) const {
  if (!(t > 0.0)) return AxisState{};  // at rest before the motion (and for NaN)
  const double end = duration();
  if (t <= end) return during(t);
  // Free flight of the table after the motion: constant final velocity.
  const AxisState last = during(end);
  return {0.0, last.velocity, last.displacement + last.velocity * (t - end)};
}

namespace {

double peak_of(const std::vector<double>& a) {
  double peak = 0.0;
  for (double ai : a) peak = std::max(peak, std::abs(ai));
  return peak;
}

void require_samples(const std::vector<double>& t, const std::vector<double>& a) {
  if (t.size() != a.size())
    throw InputError(fmt::format("sampled motion: {} times but {} accelerations", t.size(),
                                 a.size()));
  if (t.size() < 2)
    throw InputError(fmt::format("sampled motion: {} samples, at least 2 needed", t.size()));
  if (t.front() != 0.0)
    throw InputError(fmt::format("sampled motion: first time is {}, must be 0", t.front()));
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(t[i]) || !std::isfinite(a[i]))
      throw InputError(fmt::format("sampled motion: sample {} is not finite", i));
    if (i > 0 && !(t[i] > t[i - 1]))
      throw InputError(fmt::format("sampled motion: time {} at sample {} does not increase", t[i],
                                   i));
  }
}

}  // namespace

SampledAxisMotion::SampledAxisMotion(std::vector<double> t, std::vector<double> a)
    : t_(std::move(t)), a_(std::move(a)) {
  require_samples(t_, a_);
  const std::size_t n = t_.size();
  v_.assign(n, 0.0);
  d_.assign(n, 0.0);
  // Exact integrals of the linear a over [t_i, t_i + h] (docs/ground-motion.md):
  //   v_{i+1} = v_i + h (a_i + a_{i+1}) / 2
  //   d_{i+1} = d_i + h v_i + h^2 (2 a_i + a_{i+1}) / 6
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double h = t_[i + 1] - t_[i];
    v_[i + 1] = v_[i] + h * (a_[i] + a_[i + 1]) / 2.0;
    d_[i + 1] = d_[i] + h * v_[i] + h * h * (2.0 * a_[i] + a_[i + 1]) / 6.0;
  }
  samples_per_second_ = static_cast<double>(n - 1) / t_.back();
  peak_ = peak_of(a_);
}

double SampledAxisMotion::duration() const { return t_.back(); }

double SampledAxisMotion::peak_acceleration() const { return peak_; }

std::size_t SampledAxisMotion::interval(double t) const {
  const std::size_t last = t_.size() - 2;  // index of the last interval
  const std::size_t guess = std::min(static_cast<std::size_t>(t * samples_per_second_), last);
  // On uniform sampling the guess is right or, from rounding, one off.
  const std::size_t lo = guess > 0 ? guess - 1 : 0;
  for (std::size_t i = lo; i <= std::min(guess + 1, last); ++i)
    if (t_[i] <= t && t <= t_[i + 1]) return i;
  const auto above = std::upper_bound(t_.begin(), t_.end(), t);
  return std::min(static_cast<std::size_t>(above - t_.begin()) - 1, last);
}

AxisState SampledAxisMotion::during(double t) const {
  const std::size_t i = interval(t);
  const double h = t_[i + 1] - t_[i];
  const double s = t - t_[i];
  const double slope = (a_[i + 1] - a_[i]) / h;  // da/dt on the interval
  return {a_[i] + slope * s,
          v_[i] + s * (a_[i] + slope * s / 2.0),
          d_[i] + s * (v_[i] + s * (a_[i] / 2.0 + slope * s / 6.0))};
}

namespace {

// Linear interpolation of samples (t, a) at x in [t.front(), t.back()].
double interpolate(const std::vector<double>& t, const std::vector<double>& a, double x) {
  const auto above = std::upper_bound(t.begin(), t.end(), x);
  if (above == t.end()) return a.back();
  const std::size_t j = static_cast<std::size_t>(above - t.begin());
  return a[j - 1] + (a[j] - a[j - 1]) * (x - t[j - 1]) / (t[j] - t[j - 1]);
}

// The samples (t, a), t.front() = 0, on [begin, end], re-timed to start at 0.
// The cut points are interpolated, so the kept acceleration is unchanged.
void cut(const std::vector<double>& t, const std::vector<double>& a, double begin, double end,
         std::vector<double>& tc, std::vector<double>& ac) {
  tc.assign(1, 0.0);
  ac.assign(1, interpolate(t, a, begin));
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] > begin && t[i] < end) {
      tc.push_back(t[i] - begin);
      ac.push_back(a[i]);
    }
  }
  tc.push_back(end - begin);
  ac.push_back(interpolate(t, a, end));
}

// Subtracts a0 + a1 t so the motion ends at rest where it started. The line is
// piecewise linear, so the exact integrals of the corrected record at T are
//   v(T) = V - a0 T - a1 T^2 / 2,   d(T) = D - a0 T^2 / 2 - a1 T^3 / 6,
// with V, D those of the uncorrected record. Setting both to zero gives
//   [ T     T^2/2 ] [a0]   [V]        a0 =  6 D / T^2 - 2 V / T
//   [ T^2/2 T^3/6 ] [a1] = [D],  so   a1 =  6 V / T^2 - 12 D / T^3
// (determinant -T^4/12, never zero for T > 0).
void baseline_correct(const std::vector<double>& t, std::vector<double>& a) {
  const SampledAxisMotion raw(t, a);
  const double T = raw.duration();
  const AxisState end = raw.at(T);
  const double V = end.velocity, D = end.displacement;
  const double a0 = 6.0 * D / (T * T) - 2.0 * V / T;
  const double a1 = 6.0 * V / (T * T) - 12.0 * D / (T * T * T);
  for (std::size_t i = 0; i < t.size(); ++i) a[i] -= a0 + a1 * t[i];
}

void check_shaping(const RecordShaping& s, double length) {
  if (!std::isfinite(s.scale) || !std::isfinite(s.target_pga) || s.target_pga < 0.0)
    throw InputError("record shaping: scale and target_pga must be finite, target_pga >= 0");
  if (s.scale != 1.0 && s.target_pga > 0.0)
    throw InputError("record shaping: give either scale or target_pga, not both");
  if (!(s.skip >= 0.0) || !(s.duration >= 0.0))
    throw InputError("record shaping: skip and duration must be >= 0");
  if (s.skip >= length)
    throw InputError(
        fmt::format("record shaping: skip {} s is not before the record's end ({} s)", s.skip,
                    length));
  if (s.skip + s.duration > length)
    throw InputError(fmt::format(
        "record shaping: skip + duration = {} s is past the record's end ({} s)",
        s.skip + s.duration, length));
}

}  // namespace

std::unique_ptr<SampledAxisMotion> shape_record(const std::vector<double>& t,
                                                const std::vector<double>& a,
                                                const RecordShaping& shaping) {
  if (t.size() < 2 || t.size() != a.size())
    throw InputError(fmt::format("record shaping: {} times and {} values, need >= 2 of each",
                                 t.size(), a.size()));
  // Motion time is record time minus the first record time: a record that
  // starts at t0 > 0 (Michoacan: 0.02 s) plays its first sample at t = 0.
  std::vector<double> record_time(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) record_time[i] = t[i] - t.front();
  const double length = record_time.back();
  check_shaping(shaping, length);
  const double end = shaping.duration > 0.0 ? shaping.skip + shaping.duration : length;
  std::vector<double> tc, ac;
  cut(record_time, a, shaping.skip, end, tc, ac);
  if (shaping.baseline_correct) baseline_correct(tc, ac);
  double scale = shaping.scale;
  if (shaping.target_pga > 0.0) {
    const double peak = peak_of(ac);
    if (peak == 0.0) throw InputError("record shaping: target_pga of an all-zero record");
    scale = shaping.target_pga / peak;
  }
  for (double& ai : ac) ai *= scale;
  return std::make_unique<SampledAxisMotion>(std::move(tc), std::move(ac));
}

}  // namespace freestand
