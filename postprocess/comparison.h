#ifndef FREESTAND_POST_COMPARISON_H
#define FREESTAND_POST_COMPARISON_H

// Simulation against recording, one channel or all channels of a body, with
// metrics that survive the unrepeatability of rocking (peaks, decay per
// impact, residual offsets, frequency content) next to the point-by-point
// ones (normalised RMS error, time of divergence), and the time offset and
// gain between the two that rule out measurement issues. Definitions in
// docs/postprocessing.md. Plain arrays in, plain structs out; no I/O.

#include <array>
#include <vector>

#include "motion_analysis.h"

namespace freestand::comparison {

using signal::kNaN;

struct ComparisonParameters {
  double noise = 1e-4;               // standard deviation of the recording's noise, units of the channel
  double threshold_sigmas = 4;       // noise term of the divergence threshold, in standard deviations
  double divergence_window = 0.1;    // s, length of the running RMS window of the divergence test
  double divergence_fraction = 0.1;  // scale term of the divergence threshold: this fraction of the recording's peak |y|
  double max_lag = 0.5;              // s, time offsets searched within +-max_lag
  double residual_fraction = 0.1;    // residual offsets: means over the last 10 % of the compared interval
};

// The recording's samples where both the recording and the simulation
// (interpolated linearly onto the recording's times) are finite.
struct Aligned {
  std::vector<double> time;       // s
  std::vector<double> recorded;   // units of the channel
  std::vector<double> simulated;  // same units
};
Aligned align(const std::vector<double>& recorded_time, const std::vector<double>& recorded,
              const std::vector<double>& simulated_time, const std::vector<double>& simulated);

struct Spectrum {
  double dominant_frequency = kNaN;  // Hz, largest power (Hann window, log-parabola between bins)
  double centroid = kNaN;            // Hz, power-weighted mean frequency
};
// Of y (mean removed) resampled at the median step of t, gaps bridged linearly.
Spectrum spectrum(const std::vector<double>& t, const std::vector<double>& y);

// recorded(t) ~ gain * simulated(t - offset) + bias.
struct OffsetGain {
  double offset = kNaN;       // s, positive: the recording lags the simulation
  double correlation = kNaN;  // correlation coefficient at that offset
  double gain = kNaN;         // least-squares gain after removing the offset
  double gain_sd = kNaN;      // its standard deviation for the stated recording noise
  double bias = kNaN;         // least-squares constant, units of the channel
};
OffsetGain offset_and_gain(const Aligned& aligned, const std::vector<double>& simulated_time,
                           const std::vector<double>& simulated, const ComparisonParameters& parameters);

struct ChannelComparison {
  int samples = 0;                       // aligned samples compared
  double peak_recorded = kNaN;           // largest |y| of the recording (units of the channel)
  double peak_simulated = kNaN;          // largest |y| of the simulation over the same samples
  double peak_error_percent = kNaN;      // 100 (peak_simulated - peak_recorded) / peak_recorded
  double residual_recorded = kNaN;       // mean over the last residual_fraction of the interval
  double residual_simulated = kNaN;
  double residual_difference = kNaN;     // simulated - recorded
  Spectrum spectrum_recorded, spectrum_simulated;
  double nrmse = kNaN;                   // RMS(simulated - recorded) / peak_recorded
  double divergence_threshold = kNaN;    // max(k noise, fraction peak_recorded), units of the channel
  double divergence_time = kNaN;         // s, first end of a window whose RMS difference exceeds it; NaN: never
  OffsetGain offset_gain;
};
ChannelComparison compare_channel(const std::vector<double>& recorded_time, const std::vector<double>& recorded,
                                  const std::vector<double>& simulated_time, const std::vector<double>& simulated,
                                  const ComparisonParameters& parameters = {});

struct ImpactDecay {
  std::vector<double> recorded_ratios, simulated_ratios;  // |omega_after / omega_before| per impact, in order
  std::vector<double> recorded_amplitudes, simulated_amplitudes;  // rad, per half-cycle, in order
  double recorded_median = kNaN, simulated_median = kNaN;  // median ratios
};

struct BodyComparison {
  std::array<ChannelComparison, analysis::kChannelCount> channels;  // samples = 0: not in both
  std::array<ImpactDecay, 2> decay;                                 // rock_x, rock_y
};
// Every channel present in both; the noise of each is the recording's angle or
// length noise from `parameters`, the rest of `comparison` applies to all.
BodyComparison compare_body(const analysis::BodyMotion& recorded, const analysis::BodyMotion& simulated,
                            const analysis::BodyGeometry& geometry, const analysis::AnalysisParameters& parameters,
                            ComparisonParameters comparison = {});

}  // namespace freestand::comparison

#endif
