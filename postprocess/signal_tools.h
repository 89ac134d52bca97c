#ifndef FREESTAND_POST_SIGNAL_TOOLS_H
#define FREESTAND_POST_SIGNAL_TOOLS_H

// Building blocks of motion_analysis and comparison (docs/postprocessing.md):
// local least-squares fits that tolerate lost (NaN) samples and uneven
// sampling, interpolation, uniform resampling, and labelled runs of samples
// with chatter suppression. Plain arrays in, plain numbers out; no I/O.

#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

namespace freestand::signal {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Indices [first, last) of the samples with lo <= t <= hi (t ascending).
struct IndexRange {
  std::size_t first = 0, last = 0;
};
IndexRange index_range(const std::vector<double>& t, double lo, double hi);

// Polynomial of degree 1 or 2 fitted by least squares to the finite samples
// of y in `range`, expanded about t_eval.
struct LocalFit {
  bool valid = false;     // at least degree + 2 finite samples (one to spare for the noise)
  double value = kNaN;    // fitted y(t_eval), units of y
  double slope = kNaN;    // fitted dy/dt at t_eval, units of y per s
  double slope_sd = kNaN; // standard deviation of `slope` for white noise of sd `noise` on y
  double curvature = kNaN; // fitted d2y/dt2 (degree 2 only), units of y per s^2
  int samples = 0;        // finite samples used
};
LocalFit local_fit(const std::vector<double>& t, const std::vector<double>& y, IndexRange range,
                   double t_eval, int degree, double noise);

// dy/dt at every sample: straight-line fit over the finite samples within
// +-half_window s (a centred, noise-averaging difference); NaN where the
// sample itself is lost or the window holds fewer than 3 finite samples.
struct Rates {
  std::vector<double> value;  // units of y per s
  std::vector<double> sd;     // standard deviation for white noise of sd `noise` on y
};
Rates local_rates(const std::vector<double>& t, const std::vector<double>& y, double half_window,
                  double noise);

// y at xi by linear interpolation (x ascending); NaN outside [x.front(), x.back()]
// or when a bracketing sample is NaN.
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xi);

// y at t0 + k dt, k = 0..n-1, with lost samples bridged linearly between the
// finite neighbours (spectra and correlations need a gap-free uniform series);
// NaN before the first and after the last finite sample.
std::vector<double> resample_uniform(const std::vector<double>& t, const std::vector<double>& y,
                                     double t0, double dt, std::size_t n);

// y with every lost sample bridged linearly between its finite neighbours in t, and held at the
// nearest finite value before the first and after the last (a replayed table needs a value at
// every step); all NaN when no sample is finite.
std::vector<double> bridge_lost(const std::vector<double>& t, const std::vector<double>& y);

// The longest run of lost samples of y, as a bridge spans it: from the finite sample before it to
// the one after (to the record's first or last time where it has none).
struct LostSamples {
  std::size_t count = 0;   // lost samples in all
  double longest = 0;      // s: the longest bridge (0 when none is lost)
  double longest_at = kNaN; // s: the time of its first lost sample
};
LostSamples lost_samples(const std::vector<double>& t, const std::vector<double>& y);

// Median spacing of t (s): the sampling step of a recording with occasional jitter.
double median_step(const std::vector<double>& t);

// The white noise of y from its second differences: var(y[k+1] - 2 y[k] + y[k-1])
// = 6 sigma^2 for white noise, taken robustly (1.4826 x the median |difference|,
// so impacts and jumps do not count); signal content can only raise it. NaN
// with fewer than 3 finite differences.
double second_difference_noise(const std::vector<double>& y);

// A uniformly sampled series (step dt, every sample finite) with only the DFT bins whose
// frequency (Hz) `keep` accepts: the line through its end points taken out first (so its
// periodic extension has no jump; a line has no acceleration) and put back after. Zero phase.
std::vector<double> band_limited(const std::vector<double>& y, double dt, const std::function<bool(double)>& keep);

// The same series read through white noise of s.d. `noise`, with only the bins where its signal
// exceeds the noise. Each differentiation multiplies signal and noise alike by 2 pi f, so a bin
// improves a derivative only while its signal exceeds its noise: 0.5 mm of noise on a table's
// travel at 200 Hz, differentiated twice (central differences), is 12 m/s^2 rms against a
// 1 m/s^2 earthquake record.
// A bin is kept when the power spectrum of the series less its end points' line, averaged over
// 1 Hz about it (at least 5 bins), exceeds twice the noise's (signal above noise) and what the
// noise's average reaches in any bin with probability 1 %. Bands, not one cut-off: a sine test's
// harmonics stand apart. No noise: the series as it is.
struct NoiseCut {
  std::vector<double> values;  // the series with the bins kept (units of y)
  double highest_kept_hz = 0;  // the highest frequency kept (Nyquist with no noise)
};
NoiseCut cut_noise(const std::vector<double>& y, double dt, double noise);

// Mean of the finite values of y in `range`; NaN when none.
double finite_mean(const std::vector<double>& y, IndexRange range);

// Sample standard deviation of x (divisor n - 1); NaN with fewer than 2 values.
double sample_sd(const std::vector<double>& x);

// A run of equally labelled samples [first, last] (inclusive). It lasts from
// t[first] to the start of the next run (the last run: to t.back()).
struct Run {
  int label = 0;
  std::size_t first = 0, last = 0;
};
std::vector<Run> label_runs(const std::vector<int>& labels);
double run_duration(const std::vector<double>& t, const std::vector<Run>& runs, std::size_t i);

// Chatter suppression: while a run shorter than min_duration (s) remains, the
// shortest takes the label of its longer neighbour and equal neighbours join.
std::vector<Run> merge_short_runs(std::vector<Run> runs, const std::vector<double>& t,
                                  double min_duration);

}  // namespace freestand::signal

#endif
