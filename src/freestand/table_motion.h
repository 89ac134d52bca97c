#ifndef FREESTAND_TABLE_MOTION_H
#define FREESTAND_TABLE_MOTION_H

// Motion of one translational axis of a shake table as a function of time.
//
// Rocking is sensitive to how a record is interpolated (piecewise-constant
// velocity changes peak rocking by several percent at 100 Hz), so sampled
// records are treated as piecewise-LINEAR acceleration and integrated
// exactly: velocity is piecewise quadratic and displacement piecewise cubic,
// continuous in time, with no dependence on the simulation time step.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace freestand {

// Kinematics of one table axis at one instant (SI units).
struct AxisState {
  double acceleration = 0.0;  // m/s^2
  double velocity = 0.0;      // m/s
  double displacement = 0.0;  // m, relative to the table's position at t = 0
};

// One axis of table motion. Time t is measured from the start of the motion:
// for t <= 0 the table is at rest at zero displacement (a = 0 too, also at
// t = 0 exactly); after duration() the acceleration is zero (the table keeps
// its final velocity, which is zero when the motion was baseline-corrected).
// at() handles both ends once for every motion; subclasses define the motion
// on 0 < t <= duration() only. at() is const and keeps no state, so one
// motion may be queried from several threads.
class AxisMotion {
 public:
  virtual ~AxisMotion() = default;
  AxisState at(double t) const;
  virtual double duration() const = 0;  // s; infinity for an unlimited motion
  virtual double peak_acceleration() const = 0;  // max |a| over the motion, m/s^2

 protected:
  // The motion for 0 < t <= duration().
  virtual AxisState during(double t) const = 0;
};

// Piecewise-linear acceleration through samples (t_i, a_i), t_0 = 0, with
// velocity and displacement integrated exactly from rest (docs/ground-motion.md).
// Lookup of the interval holding t is O(1) on (nearly) uniform sampling: the
// guess t / mean spacing is checked and its neighbours, with a binary search
// as fallback, so no mutable "last interval" hint is needed.
class SampledAxisMotion : public AxisMotion {
 public:
  // t strictly increasing, t.front() == 0, same length as a (>= 2 samples),
  // all finite. Throws InputError otherwise.
  SampledAxisMotion(std::vector<double> t, std::vector<double> a);
  double duration() const override;
  double peak_acceleration() const override;

  const std::vector<double>& times() const { return t_; }
  const std::vector<double>& accelerations() const { return a_; }

 protected:
  AxisState during(double t) const override;

 private:
  std::size_t interval(double t) const;  // i with t_[i] <= t <= t_[i+1]

  std::vector<double> t_;  // sample times, strictly increasing, t_[0] = 0
  std::vector<double> a_;  // acceleration at t_[i]
  std::vector<double> v_;  // exact velocity at t_[i]
  std::vector<double> d_;  // exact displacement at t_[i]
  double samples_per_second_ = 0.0;  // (n-1)/duration, for the interval guess
  double peak_ = 0.0;                // max |a_i|: exact for piecewise-linear a
};

// How a sampled record becomes table motion.
struct RecordShaping {
  double scale = 1.0;          // multiply accelerations by this ...
  double target_pga = 0.0;     // ... or, when > 0, scale so that max |a| is this (m/s^2)
  double skip = 0.0;           // s of the record to skip before playing it
  double duration = 0.0;       // s of the record to play after skip; 0: to its end
  bool baseline_correct = false;  // subtract a0 + a1 t so the table ends at rest where it started
};

// Applies shaping to accelerations a(t) (SI) and returns the table motion.
// Motion time is record time minus t.front(): a record starting at t0 > 0
// plays its first sample at t = 0. Steps, in this order: cut [skip, skip +
// duration] (the cut points are interpolated linearly, so the played
// acceleration is exactly the record's on the kept interval), baseline
// correction of the cut record, then scaling (so target_pga is the peak of
// what is played). Throws InputError on contradictory shaping (both scale != 1
// and target_pga, skip or skip + duration past the end, all-zero record with
// target_pga).
std::unique_ptr<SampledAxisMotion> shape_record(const std::vector<double>& t,
                                                const std::vector<double>& a,
                                                const RecordShaping& shaping);

// Built-in analytic motions for validation; v and d in closed form where
// one exists (formulas in docs/ground-motion.md). All start at rest at t = 0.
//   sine      A sin(2 pi f t) for `duration` s (0: unlimited, duration() = inf)
//   onesine   one full period, 1/f s; ends at rest, displaced by A / (2 pi f^2)
//   ricker    A (1 - 2 u^2) exp(-u^2), u = pi f (t - ts), played on [0, 2 ts]
//   rectangle A for `width` s; the table then moves on at A width
//   sweep     A sin(2 pi (f0 t + (f1 - f0) t^2 / (2 T))) for T = `duration` s,
//             sampled so that |a error| <= 1e-4 A, integrated as a record
// Parameters a kind does not use must stay 0.
struct AnalyticMotionSpec {
  std::string kind;          // "sine", "onesine", "ricker", "rectangle", "sweep"
  double amplitude = 0.0;    // peak acceleration, m/s^2 (sign: polarity)
  double frequency = 0.0;    // Hz: sine, onesine (one full period), ricker (peak frequency), sweep start
  double frequency_end = 0.0;  // Hz: sweep end frequency
  double width = 0.0;        // s: rectangle duration; ricker centre time ts (default 1.5/f when 0)
  double duration = 0.0;     // s: sine and sweep length (sine: 0 means unlimited)
};
// Throws InputError on an unknown kind or a missing/invalid parameter.
std::unique_ptr<AxisMotion> make_analytic_motion(const AnalyticMotionSpec& spec);

}  // namespace freestand

#endif
