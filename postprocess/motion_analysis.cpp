#include "motion_analysis.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "freestand/input_error.h"

namespace freestand::analysis {

using signal::IndexRange;
using signal::index_range;
using signal::local_fit;
using signal::local_rates;
using signal::Rates;

namespace {

int sign(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

// The channel, or `fill` at every sample when it was not measured.
std::vector<double> series(const BodyMotion& motion, int channel, double fill) {
  const auto& values = motion.channels[channel];
  return values.empty() ? std::vector<double>(motion.time.size(), fill) : values;
}

// Rates of a series: the given exact ones, else fitted. The standard deviation
// is always the fit's, so thresholds are the same either way.
Rates rates_of(const BodyMotion& motion, const std::vector<double>& values,
               const std::vector<double>& exact, double noise, const AnalysisParameters& p) {
  Rates rates = local_rates(motion.time, values, p.rate_half_window, noise);
  if (!exact.empty()) rates.value = exact;
  return rates;
}

// Horizontal motion of the base centre caused by rocking on a base edge at
// distance b: sgn(theta) b (1 - cos theta) (m). Zero when b is unknown.
double rocking_slide(double theta, double b) {
  return std::isfinite(b) ? sign(theta) * b * (1 - std::cos(theta)) : 0.0;
}

double rocking_slide_rate(double theta, double theta_rate, double b) {
  return std::isfinite(b) ? b * std::fabs(std::sin(theta)) * theta_rate : 0.0;
}

}  // namespace

void check_motion(const BodyMotion& motion, const AnalysisParameters& p) {
  const std::size_t n = motion.time.size();
  if (n < 3) throw InputError(fmt::format("motion analysis: {} time samples, need >= 3", n));
  for (std::size_t i = 1; i < n; ++i)
    if (!(motion.time[i] > motion.time[i - 1]))
      throw InputError(fmt::format("motion analysis: time not strictly increasing at sample {}", i));
  auto check_length = [&](const std::vector<double>& v, const std::string& what) {
    if (!v.empty() && v.size() != n)
      throw InputError(fmt::format("motion analysis: {} has {} samples, time has {}", what, v.size(), n));
  };
  for (int c = 0; c < kChannelCount; ++c) {
    check_length(motion.channels[c], fmt::format("channel {}", c));
    check_length(motion.rates[c], fmt::format("rate of channel {}", c));
  }
  check_length(motion.support_uplift, "support_uplift");
  const std::pair<double, const char*> positive[] = {
      {p.angle_noise, "angle_noise"},         {p.length_noise, "length_noise"},
      {p.threshold_sigmas, "threshold_sigmas"}, {p.rate_half_window, "rate_half_window"},
      {p.residual_fraction, "residual_fraction"}, {p.impact_window, "impact_window"}};
  for (const auto& [value, name] : positive)
    if (!(value > 0)) throw InputError(fmt::format("motion analysis: parameter {} = {} must be > 0", name, value));
  if (!(p.min_segment >= 0) || !(p.overturn_margin >= 0) || p.residual_fraction > 1)
    throw InputError("motion analysis: min_segment and overturn_margin must be >= 0, residual_fraction <= 1");
}

namespace {

// Peak of |theta| near sample `best`: vertex of a parabola fitted to the
// two finite samples on each side of it and itself (lost samples are skipped,
// up to kPeakReach steps away) when the vertex lies among them, else the sample.
double refined_peak(const std::vector<double>& t, const std::vector<double>& theta, std::size_t best) {
  constexpr std::size_t kPeakReach = 8;  // samples; beyond that the parabola no longer fits a peak
  auto reach = [&](int direction) {
    std::size_t i = best;
    for (int found = 0; found < 2; ) {
      if ((direction < 0 && i == 0) || (direction > 0 && i + 1 == t.size()) || std::max(i, best) - std::min(i, best) >= kPeakReach)
        break;
      i += direction;
      if (std::isfinite(theta[i])) ++found;
    }
    return i;
  };
  const IndexRange range{reach(-1), reach(+1) + 1};
  const signal::LocalFit fit = local_fit(t, theta, range, t[best], 2, 0.0);
  if (fit.valid && fit.curvature * theta[best] < 0) {
    const double shift = -fit.slope / fit.curvature;
    if (t[best] + shift >= t[range.first] && t[best] + shift <= t[range.last - 1])
      return std::fabs(fit.value - fit.slope * fit.slope / (2 * fit.curvature));
  }
  return std::fabs(theta[best]);
}

// Largest |theta| strictly between times lo and hi; NaN when the largest
// sample is at an end of the record (the peak is not inside it).
double half_cycle_amplitude(const std::vector<double>& t, const std::vector<double>& theta, double lo,
                            double hi) {
  const IndexRange range = index_range(t, lo, hi);
  std::size_t best = range.last;
  for (std::size_t i = range.first; i < range.last; ++i)
    if (std::isfinite(theta[i]) && (best == range.last || std::fabs(theta[i]) > std::fabs(theta[best])))
      best = i;
  if (best == range.last || best + 1 == t.size()) return kNaN;
  return refined_peak(t, theta, best);
}

// Zero crossings of theta that complete a change of sign: |theta| must exceed
// `hysteresis` on both sides. Returns the interpolated time of the last
// crossing before each such change.
std::vector<double> hysteresis_crossings(const std::vector<double>& t, const std::vector<double>& theta,
                                         double hysteresis) {
  std::vector<double> crossings;
  int side = 0;  // sign of the current half-cycle, once |theta| has exceeded the hysteresis
  double last_crossing = kNaN;
  std::size_t previous = t.size();  // last finite sample
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(theta[i])) continue;
    if (previous < t.size() && sign(theta[previous]) * sign(theta[i]) < 0)
      last_crossing = t[previous] + (t[i] - t[previous]) * theta[previous] / (theta[previous] - theta[i]);
    previous = i;
    if (std::fabs(theta[i]) <= hysteresis) continue;
    if (side != 0 && sign(theta[i]) != side && std::isfinite(last_crossing)) crossings.push_back(last_crossing);
    side = sign(theta[i]);
  }
  return crossings;
}

double median(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }),
               values.end());
  if (values.empty()) return kNaN;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  if (values.size() % 2) return values[mid];
  return 0.5 * (values[mid] + *std::max_element(values.begin(), values.begin() + mid));
}

Impact impact_at(const std::vector<double>& t, const std::vector<double>& theta,
                 const std::vector<double>& crossings, std::size_t k, const AnalysisParameters& p) {
  const double crossing = crossings[k];
  const double before = k > 0 ? crossings[k - 1] : t.front();
  const double after = k + 1 < crossings.size() ? crossings[k + 1] : t.back();
  // The fit windows stay inside the neighbouring half-cycles (half of each at most).
  const double window = std::min({p.impact_window, 0.5 * (crossing - before), 0.5 * (after - crossing)});
  const IndexRange left = index_range(t, crossing - window, crossing);
  const IndexRange right = index_range(t, std::nextafter(crossing, after), crossing + window);
  // The angular velocity jumps at the impact, so linear interpolation of the
  // crossing errs by up to (1 - r) dt / 4: the impact is where the one-sided
  // fits reach zero (one Newton step from the crossing, mean of both sides).
  auto fit_at = [&](IndexRange range, double time) { return local_fit(t, theta, range, time, 2, p.angle_noise); };
  auto root_shift = [](const signal::LocalFit& fit) { return fit.valid ? -fit.value / fit.slope : kNaN; };
  const double shift = 0.5 * (root_shift(fit_at(left, crossing)) + root_shift(fit_at(right, crossing)));
  Impact impact;
  impact.time = std::isfinite(shift) ? crossing + shift : crossing;
  const signal::LocalFit fit_before = fit_at(left, impact.time), fit_after = fit_at(right, impact.time);
  impact.omega_before = fit_before.slope;
  impact.omega_after = fit_after.slope;
  impact.omega_before_sd = fit_before.slope_sd;
  impact.omega_after_sd = fit_after.slope_sd;
  impact.ratio = std::fabs(fit_after.slope / fit_before.slope);
  impact.ratio_sd = impact.ratio * std::hypot(fit_after.slope_sd / fit_after.slope,
                                              fit_before.slope_sd / fit_before.slope);
  impact.amplitude_before = half_cycle_amplitude(t, theta, before, crossing);
  impact.amplitude_after = half_cycle_amplitude(t, theta, crossing, after);
  return impact;
}

// Segments of the runs whose label is `wanted` (after chatter suppression).
std::vector<signal::Run> runs_labelled(const std::vector<int>& labels, const std::vector<double>& t,
                                       double min_duration, int wanted) {
  std::vector<signal::Run> kept;
  for (const signal::Run& run : signal::merge_short_runs(signal::label_runs(labels), t, min_duration))
    if (run.label == wanted) kept.push_back(run);
  return kept;
}

double run_end(const std::vector<double>& t, const signal::Run& run) {
  return run.last + 1 < t.size() ? t[run.last + 1] : t.back();
}

// First finite value of y at or after index i (forward) or at or before it (backward).
double finite_near(const std::vector<double>& y, std::size_t i, bool forward) {
  for (std::size_t k = i; k < y.size(); forward ? ++k : --k)
    if (std::isfinite(y[k])) return y[k];
  return kNaN;
}

}  // namespace

bool BodyGeometry::known(int axis) const {
  return std::isfinite(axis == 0 ? half_width_x : half_width_y) && std::isfinite(com_height);
}

double BodyGeometry::slenderness(int axis) const {
  return std::atan2(axis == 0 ? half_width_x : half_width_y, com_height);
}

double BodyGeometry::housner_ratio(int axis) const {
  const double s = std::sin(slenderness(axis));
  return 1 - 1.5 * s * s;
}

double BodyGeometry::rocking_rise(double rock_x, double rock_y) const {
  auto rise = [&](double theta, double b) {
    return std::isfinite(b) ? com_height * (std::cos(theta) - 1) + b * std::sin(std::fabs(theta)) : 0.0;
  };
  return rise(rock_x, half_width_x) + rise(rock_y, half_width_y);
}

ChannelSeries channel_rates(const std::vector<Eigen::Quaterniond>& orientation,
                            const std::vector<Eigen::Vector3d>& omega,
                            const std::vector<Eigen::Vector3d>& com_velocity,
                            const std::vector<Eigen::Vector3d>& support_velocity,
                            const Eigen::Vector3d& com_in_body) {
  const std::size_t n = orientation.size();
  if (omega.size() != n || com_velocity.size() != n || (!support_velocity.empty() && support_velocity.size() != n))
    throw InputError("channel_rates: orientation, omega, com_velocity and support_velocity differ in length");
  ChannelSeries rates;
  for (auto& r : rates) r.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d rotation = orientation[i].toRotationMatrix();
    const Eigen::Vector3d e1 = rotation.col(0), e3 = rotation.col(2);
    const Eigen::Vector3d de1 = omega[i].cross(e1), de3 = omega[i].cross(e3);
    // d/dt atan2(a, b) = (b a' - a b') / (a^2 + b^2)
    auto atan2_rate = [](double a, double b, double da, double db) { return (b * da - a * db) / (a * a + b * b); };
    rates[kRockX][i] = atan2_rate(e3.x(), e3.z(), de3.x(), de3.z());
    rates[kRockY][i] = atan2_rate(e3.y(), e3.z(), de3.y(), de3.z());
    rates[kTwist][i] = atan2_rate(e1.y(), e1.x(), de1.y(), de1.x());
    // Base centre = COM - R c: its velocity is v - omega x (R c).
    Eigen::Vector3d base = com_velocity[i] - omega[i].cross(rotation * com_in_body);
    if (!support_velocity.empty()) base -= support_velocity[i];
    rates[kSlideX][i] = base.x();
    rates[kSlideY][i] = base.y();
    rates[kUplift][i] = com_velocity[i].z();
  }
  return rates;
}

double tilt(double rock_x, double rock_y) {
  // e3 up to a positive factor: e3.x / e3.z = tan(rock_x), e3.y / e3.z =
  // tan(rock_y), and the signs of the components those atan2 values imply.
  const Eigen::Vector3d e3(std::sin(rock_x) * std::fabs(std::cos(rock_y)),
                           std::sin(rock_y) * std::fabs(std::cos(rock_x)),
                           std::cos(rock_x) * std::fabs(std::cos(rock_y)));
  return std::acos(std::clamp(e3.z() / e3.norm(), -1.0, 1.0));
}

double Peak::magnitude() const { return std::max(std::fabs(max), std::fabs(min)); }

std::array<Peak, kChannelCount> channel_peaks(const BodyMotion& motion) {
  std::array<Peak, kChannelCount> peaks;
  for (int c = 0; c < kChannelCount; ++c) {
    const auto& y = motion.channels[c];
    for (std::size_t i = 0; i < y.size(); ++i) {
      if (!std::isfinite(y[i])) continue;
      Peak& peak = peaks[c];
      if (!(y[i] <= peak.max)) peak.max = y[i], peak.t_max = motion.time[i];
      if (!(y[i] >= peak.min)) peak.min = y[i], peak.t_min = motion.time[i];
    }
  }
  return peaks;
}

Residuals residuals(const BodyMotion& motion, const AnalysisParameters& p) {
  Residuals out;
  const double end = motion.time.back();
  out.window_start = end - p.residual_fraction * (end - motion.time.front());
  const IndexRange range = index_range(motion.time, out.window_start, end);
  for (int c = 0; c < kChannelCount; ++c)
    out.mean[c] = motion.channels[c].empty() ? kNaN : signal::finite_mean(motion.channels[c], range);
  return out;
}

const char* mode_name(Mode mode) {
  switch (mode) {
    case Mode::lost: return "lost";
    case Mode::rest: return "rest";
    case Mode::rock: return "rock";
    case Mode::slide: return "slide";
    case Mode::slide_rock: return "slide-rock";
    case Mode::twist: return "twist";
    case Mode::flight: return "flight";
    case Mode::overturned: return "overturned";
  }
  return "?";
}

ModeEvidence mode_evidence(const BodyMotion& motion, const BodyGeometry& geometry,
                           const AnalysisParameters& p) {
  const std::size_t n = motion.time.size();
  const double k = p.threshold_sigmas;
  const std::vector<double> rock_x = series(motion, kRockX, 0.0), rock_y = series(motion, kRockY, 0.0);
  const Rates rock_x_rate = rates_of(motion, rock_x, motion.rates[kRockX], p.angle_noise, p);
  const Rates rock_y_rate = rates_of(motion, rock_y, motion.rates[kRockY], p.angle_noise, p);
  const Rates twist_rate =
      rates_of(motion, series(motion, kTwist, 0.0), motion.rates[kTwist], p.angle_noise, p);
  const std::vector<double> slide_x = series(motion, kSlideX, 0.0), slide_y = series(motion, kSlideY, 0.0);
  const std::vector<double> uplift = series(motion, kUplift, kNaN);

  ModeEvidence e;
  e.slip_x.resize(n);
  e.slip_y.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    e.slip_x[i] = slide_x[i] - rocking_slide(rock_x[i], geometry.half_width_x);
    e.slip_y[i] = slide_y[i] - rocking_slide(rock_y[i], geometry.half_width_y);
  }
  // Exact slide rates become slip rates by removing the rocking part too.
  auto exact_slip_rate = [&](int slide, const std::vector<double>& theta, const Rates& theta_rate, double b) {
    std::vector<double> rate = motion.rates[slide];
    for (std::size_t i = 0; i < rate.size(); ++i) rate[i] -= rocking_slide_rate(theta[i], theta_rate.value[i], b);
    return rate;
  };
  const Rates slip_x_rate = rates_of(motion, e.slip_x, exact_slip_rate(kSlideX, rock_x, rock_x_rate, geometry.half_width_x),
                                     p.length_noise, p);
  const Rates slip_y_rate = rates_of(motion, e.slip_y, exact_slip_rate(kSlideY, rock_y, rock_y_rate, geometry.half_width_y),
                                     p.length_noise, p);

  // Uplift beyond the rocking rise (relative to the first sample's, since
  // uplift is measured from the initial state); noise of the rise: b sd_angle.
  double rise0 = kNaN;
  const bool geometry_known = geometry.known(0) || geometry.known(1);
  const double rise_noise = std::hypot(std::isfinite(geometry.half_width_x) ? geometry.half_width_x : 0.0,
                                       std::isfinite(geometry.half_width_y) ? geometry.half_width_y : 0.0) *
                            p.angle_noise;
  const double gap_threshold = k * std::hypot(p.length_noise, rise_noise);
  e.excess_uplift.assign(n, kNaN);
  for (std::size_t i = 0; i < n && geometry_known; ++i) {
    const double rise = geometry.rocking_rise(rock_x[i], rock_y[i]);
    if (std::isnan(rise0)) rise0 = rise;
    const double support = motion.support_uplift.empty() ? 0.0 : motion.support_uplift[i];
    e.excess_uplift[i] = uplift[i] - support - (rise - rise0);
  }

  auto beyond = [&](double value, double sd) { return std::fabs(value) > k * sd; };
  for (std::size_t i = 0; i < n; ++i) {
    e.rocking.push_back(beyond(rock_x[i], p.angle_noise) || beyond(rock_y[i], p.angle_noise) ||
                        beyond(rock_x_rate.value[i], rock_x_rate.sd[i]) ||
                        beyond(rock_y_rate.value[i], rock_y_rate.sd[i]));
    const double vx = std::isfinite(slip_x_rate.value[i]) ? slip_x_rate.value[i] : 0.0;
    const double vy = std::isfinite(slip_y_rate.value[i]) ? slip_y_rate.value[i] : 0.0;
    const double speed_sd = std::fmax(slip_x_rate.sd[i], slip_y_rate.sd[i]);  // fmax: NaN-free when one is
    e.slip_speed.push_back(std::hypot(vx, vy));
    e.sliding.push_back(beyond(e.slip_speed.back(), speed_sd));
    e.twisting.push_back(beyond(twist_rate.value[i], twist_rate.sd[i]));
    e.flying.push_back(e.excess_uplift[i] > gap_threshold);
    bool known = false;
    for (int c = 0; c < kChannelCount; ++c)
      known = known || (!motion.channels[c].empty() && std::isfinite(motion.channels[c][i]));
    e.known.push_back(known);
  }
  return e;
}

Overturn detect_overturn(const BodyMotion& motion, const BodyGeometry& geometry, const AnalysisParameters& p) {
  const std::vector<double> rock[2] = {series(motion, kRockX, 0.0), series(motion, kRockY, 0.0)};
  Rates rates[2];
  for (int axis = 0; axis < 2; ++axis)
    rates[axis] = rates_of(motion, rock[axis], motion.rates[kRockX + axis], p.angle_noise, p);
  // Overturning is a transition: a criterion counts only after a sample that
  // did not meet it (a body released beyond alpha, or tossed and tumbling, is
  // not "overturned" at its first sample).
  Overturn out;
  bool stood[2] = {false, false}, upright = false;
  for (std::size_t i = 0; i < motion.time.size(); ++i) {
    for (int axis = 0; axis < 2; ++axis) {
      if (!geometry.known(axis)) continue;
      const double theta = rock[axis][i];
      const bool beyond = std::fabs(theta) > geometry.slenderness(axis) + p.overturn_margin;
      const bool growing = sign(theta) * rates[axis].value[i] > p.threshold_sigmas * rates[axis].sd[i];
      if (beyond && growing && stood[axis]) {
        out = {true, motion.time[i], fmt::format("{} beyond alpha + margin and growing", axis ? "rock_y" : "rock_x")};
        return out;
      }
      stood[axis] = stood[axis] || !beyond;
    }
    const bool lying = tilt(rock[0][i], rock[1][i]) >= M_PI / 2 - p.overturn_margin;
    if (lying && upright) {
      out = {true, motion.time[i], "lying on a side"};
      return out;
    }
    upright = upright || !lying;
  }
  return out;
}

std::vector<ModeSegment> mode_timeline(const BodyMotion& motion, const ModeEvidence& e,
                                       const Overturn& overturn, const AnalysisParameters& p) {
  const std::vector<double>& t = motion.time;
  std::vector<int> labels(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    Mode mode = Mode::rest;
    if (!e.known[i]) mode = Mode::lost;
    else if (overturn.overturned && t[i] >= overturn.time) mode = Mode::overturned;
    else if (e.flying[i]) mode = Mode::flight;
    else if (e.rocking[i] && e.sliding[i]) mode = Mode::slide_rock;
    else if (e.rocking[i]) mode = Mode::rock;
    else if (e.sliding[i]) mode = Mode::slide;
    else if (e.twisting[i]) mode = Mode::twist;
    labels[i] = static_cast<int>(mode);
  }
  std::vector<ModeSegment> segments;
  for (const signal::Run& run : signal::merge_short_runs(signal::label_runs(labels), t, p.min_segment))
    segments.push_back({static_cast<Mode>(run.label), t[run.first], run_end(t, run)});
  return segments;
}

std::vector<SlipEvent> slip_events(const BodyMotion& motion, const ModeEvidence& e, const AnalysisParameters& p) {
  // Lost samples get their own label, so short gaps are bridged by the
  // chatter suppression and long ones end an event.
  std::vector<int> labels(motion.time.size());
  for (std::size_t i = 0; i < labels.size(); ++i) labels[i] = e.known[i] ? e.sliding[i] : 2;
  std::vector<SlipEvent> events;
  for (const signal::Run& run : runs_labelled(labels, motion.time, p.min_segment, 1)) {
    SlipEvent event;
    event.onset = motion.time[run.first];
    event.stop = run_end(motion.time, run);
    const std::size_t after = std::min(run.last + 1, motion.time.size() - 1);
    event.slip_x = finite_near(e.slip_x, after, false) - finite_near(e.slip_x, run.first, true);
    event.slip_y = finite_near(e.slip_y, after, false) - finite_near(e.slip_y, run.first, true);
    event.peak_speed = *std::max_element(e.slip_speed.begin() + run.first, e.slip_speed.begin() + run.last + 1);
    events.push_back(event);
  }
  return events;
}

std::vector<Separation> separations(const BodyMotion& motion, const ModeEvidence& e, const AnalysisParameters& p) {
  std::vector<int> labels(e.flying.begin(), e.flying.end());
  std::vector<Separation> out;
  for (const signal::Run& run : runs_labelled(labels, motion.time, p.min_segment, 1)) {
    double gap = kNaN;
    for (std::size_t i = run.first; i <= run.last; ++i) gap = std::fmax(gap, e.excess_uplift[i]);
    out.push_back({motion.time[run.first], run_end(motion.time, run), gap});
  }
  return out;
}

RockingImpacts rocking_impacts(const BodyMotion& motion, int axis, const BodyGeometry& geometry,
                               const AnalysisParameters& p) {
  RockingImpacts out;
  if (geometry.known(axis)) out.housner_ratio = geometry.housner_ratio(axis);
  const std::vector<double>& theta = motion.channels[kRockX + axis];
  if (theta.empty()) return out;
  const std::vector<double>& t = motion.time;
  const std::vector<double> crossings = hysteresis_crossings(t, theta, p.threshold_sigmas * p.angle_noise);
  std::vector<double> ratios;
  for (std::size_t k = 0; k < crossings.size(); ++k) {
    out.impacts.push_back(impact_at(t, theta, crossings, k, p));
    // The median counts impacts that arrive with a measurable angular
    // velocity: a crossing that merely grazes zero (a driven body barely
    // rocking) has omega_before ~ 0 and an arbitrary ratio.
    const Impact& i = out.impacts.back();
    if (std::fabs(i.omega_before) > p.threshold_sigmas * i.omega_before_sd) ratios.push_back(i.ratio);
    if (k > 0) out.half_cycles.push_back({out.impacts[k - 1].time, out.impacts[k].time, out.impacts[k - 1].amplitude_after});
  }
  out.median_ratio = median(ratios);
  return out;
}

MotionSummary analyse_motion(const BodyMotion& motion, const BodyGeometry& geometry, const AnalysisParameters& p) {
  check_motion(motion, p);
  MotionSummary summary;
  summary.peaks = channel_peaks(motion);
  summary.residual = residuals(motion, p);
  summary.overturn = detect_overturn(motion, geometry, p);
  const ModeEvidence evidence = mode_evidence(motion, geometry, p);
  summary.modes = mode_timeline(motion, evidence, summary.overturn, p);
  for (int axis = 0; axis < 2; ++axis) summary.impacts[axis] = rocking_impacts(motion, axis, geometry, p);
  summary.slips = slip_events(motion, evidence, p);
  summary.separations = separations(motion, evidence, p);
  return summary;
}

}  // namespace freestand::analysis
