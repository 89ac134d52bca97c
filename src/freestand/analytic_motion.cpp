// Built-in analytic table motions (formulas in docs/ground-motion.md).

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <memory>
#include <vector>

#include "freestand/input_error.h"
#include "freestand/table_motion.h"

namespace freestand {

namespace {

constexpr double kPi = 3.14159265358979323846;

// a = A sin(w t) on 0 < t <= T (T infinite: unlimited), from rest:
//   v = A (1 - cos w t) / w,   d = A (t - sin(w t) / w) / w.
// The mean velocity A / w is not zero, so the table drifts.
class SineMotion : public AxisMotion {
 public:
  SineMotion(double amplitude, double frequency, double duration)
      : A_(amplitude), w_(2.0 * kPi * frequency), T_(duration) {}
  double duration() const override { return T_; }
  double peak_acceleration() const override {
    // |sin| reaches 1 at w t = pi/2; a shorter motion peaks at its end.
    return std::abs(A_) * (w_ * T_ >= kPi / 2.0 ? 1.0 : std::sin(w_ * T_));
  }

 protected:
  AxisState during(double t) const override {
    const double wt = w_ * t;
    return {A_ * std::sin(wt), A_ * (1.0 - std::cos(wt)) / w_, A_ * (t - std::sin(wt) / w_) / w_};
  }

 private:
  double A_;  // amplitude, m/s^2
  double w_;  // angular frequency, rad/s
  double T_;  // duration, s (infinity: unlimited)
};

// a = A (1 - 2 u^2) exp(-u^2), u = pi f (t - ts), on 0 < t <= 2 ts.
// Since d/dt[(t - ts) exp(-u^2)] = (1 - 2 u^2) exp(-u^2), from rest
//   v = A [(t - ts) exp(-u^2) + ts e0],   e0 = exp(-(pi f ts)^2),
//   d = A [(e0 - exp(-u^2)) / (2 pi^2 f^2) + ts e0 t].
// The wavelet is not zero at t = 0 (a(0+) = A (1 - 2 (pi f ts)^2) e0, about
// -1e-8 A for ts = 1.5/f) nor after 2 ts; both tails are cut.
class RickerMotion : public AxisMotion {
 public:
  RickerMotion(double amplitude, double frequency, double centre)
      : A_(amplitude), pf_(kPi * frequency), ts_(centre),
        e0_(std::exp(-pf_ * pf_ * centre * centre)) {}
  double duration() const override { return 2.0 * ts_; }
  double peak_acceleration() const override { return std::abs(A_); }  // at t = ts

 protected:
  AxisState during(double t) const override {
    const double x = t - ts_;
    const double g = std::exp(-pf_ * pf_ * x * x);
    return {A_ * (1.0 - 2.0 * pf_ * pf_ * x * x) * g, A_ * (x * g + ts_ * e0_),
            A_ * ((e0_ - g) / (2.0 * pf_ * pf_) + ts_ * e0_ * t)};
  }

 private:
  double A_;   // amplitude, m/s^2
  double pf_;  // pi times the peak frequency, 1/s
  double ts_;  // centre time, s
  double e0_;  // exp(-(pi f ts)^2): the wavelet's envelope at t = 0
};

// a = A on 0 < t <= W: v = A t, d = A t^2 / 2; the table then moves on at A W.
class RectangleMotion : public AxisMotion {
 public:
  RectangleMotion(double amplitude, double width) : A_(amplitude), W_(width) {}
  double duration() const override { return W_; }
  double peak_acceleration() const override { return std::abs(A_); }

 protected:
  AxisState during(double t) const override { return {A_, A_ * t, A_ * t * t / 2.0}; }

 private:
  double A_;  // amplitude, m/s^2
  double W_;  // pulse width, s
};

// Relative error bound of the sampled sweep's acceleration (see make_sweep).
constexpr double kSweepTolerance = 1e-4;

// Linear chirp a = A sin(phi), phi = 2 pi (f0 t + (f1 - f0) t^2 / (2 T)), on
// 0 < t <= T, sampled and integrated as piecewise-linear acceleration. Linear
// interpolation errs by at most h^2 max|a''| / 8, and
// |a''| <= A (phi'^2 + |phi''|), so the step below keeps |a - a_sampled| <=
// kSweepTolerance * A; v and d, integrals of a, inherit that relative error.
std::unique_ptr<AxisMotion> make_sweep(const AnalyticMotionSpec& s) {
  const double f0 = s.frequency, f1 = s.frequency_end, T = s.duration;
  const double w_max = 2.0 * kPi * std::max(std::abs(f0), std::abs(f1));
  const double chirp = 2.0 * kPi * std::abs(f1 - f0) / T;  // |phi''|
  const double h = std::sqrt(8.0 * kSweepTolerance / (w_max * w_max + chirp));
  const std::size_t n = static_cast<std::size_t>(std::ceil(T / h)) + 1;
  std::vector<double> t(n), a(n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = T * static_cast<double>(i) / static_cast<double>(n - 1);
    a[i] = s.amplitude * std::sin(2.0 * kPi * t[i] * (f0 + (f1 - f0) * t[i] / (2.0 * T)));
  }
  return std::make_unique<SampledAxisMotion>(std::move(t), std::move(a));
}

void require(bool ok, const AnalyticMotionSpec& s, const char* what) {
  if (!ok) throw InputError(fmt::format("analytic motion '{}': {}", s.kind, what));
}

// Parameters a kind does not use must be left at 0, so that a misspelt
// intention (e.g. a duration for onesine) is not silently ignored.
void require_unused(const AnalyticMotionSpec& s, bool frequency, bool frequency_end, bool width,
                    bool duration) {
  require(!frequency || s.frequency == 0.0, s, "frequency is not a parameter of this motion");
  require(!frequency_end || s.frequency_end == 0.0, s,
          "frequency_end is not a parameter of this motion");
  require(!width || s.width == 0.0, s, "width is not a parameter of this motion");
  require(!duration || s.duration == 0.0, s, "duration is not a parameter of this motion");
}

}  // namespace

std::unique_ptr<AxisMotion> make_analytic_motion(const AnalyticMotionSpec& s) {
  require(std::isfinite(s.amplitude) && s.amplitude != 0.0, s, "amplitude must be finite, != 0");
  require(std::isfinite(s.frequency) && std::isfinite(s.frequency_end) &&
              std::isfinite(s.width) && std::isfinite(s.duration),
          s, "parameters must be finite");
  const bool positive_f = s.frequency > 0.0;
  if (s.kind == "sine") {
    require(positive_f, s, "frequency must be > 0");
    require(s.duration >= 0.0, s, "duration must be >= 0 (0: unlimited)");
    require_unused(s, false, true, true, false);
    const double T = s.duration > 0.0 ? s.duration : std::numeric_limits<double>::infinity();
    return std::make_unique<SineMotion>(s.amplitude, s.frequency, T);
  }
  if (s.kind == "onesine") {
    require(positive_f, s, "frequency must be > 0");
    require_unused(s, false, true, true, true);
    return std::make_unique<SineMotion>(s.amplitude, s.frequency, 1.0 / s.frequency);
  }
  if (s.kind == "ricker") {
    require(positive_f, s, "frequency must be > 0");
    require(s.width >= 0.0, s, "width (centre time) must be >= 0 (0: 1.5/frequency)");
    require_unused(s, false, true, false, true);
    const double ts = s.width > 0.0 ? s.width : 1.5 / s.frequency;
    return std::make_unique<RickerMotion>(s.amplitude, s.frequency, ts);
  }
  if (s.kind == "rectangle") {
    require(s.width > 0.0, s, "width must be > 0");
    require_unused(s, true, true, false, true);
    return std::make_unique<RectangleMotion>(s.amplitude, s.width);
  }
  if (s.kind == "sweep") {
    require(s.frequency >= 0.0 && s.frequency_end >= 0.0 &&
                std::max(s.frequency, s.frequency_end) > 0.0,
            s, "frequencies must be >= 0 and not both 0");
    require(s.duration > 0.0, s, "duration must be > 0");
    require_unused(s, false, false, true, false);
    return make_sweep(s);
  }
  throw InputError(fmt::format(
      "analytic motion: unknown kind '{}' (expected sine, onesine, ricker, rectangle, sweep)",
      s.kind));
}

}  // namespace freestand
