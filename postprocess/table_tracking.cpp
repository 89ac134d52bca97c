#include "table_tracking.h"

#include <fmt/format.h>

#include <cmath>

#include "comparison.h"

namespace freestand {

namespace {

constexpr double kMaxLag = 0.5;       // s, offsets searched (a servo lags by milliseconds)
constexpr double kSignificance = 4;   // s.d.: with three estimates per axis, a false alarm well below 1e-3

double root_mean_square(const std::vector<double>& y) {
  double sum = 0;
  for (double v : y) sum += v * v;
  return y.empty() ? signal::kNaN : std::sqrt(sum / y.size());
}

// The command along one axis, sampled finely enough to interpolate linearly
// (1/8 of the recording's step) over the recording plus the lags searched.
struct SampledCommand {
  std::vector<double> time, acceleration;
};
SampledCommand sample_command(const ShakeTable& command, int axis, double start, double end, double step) {
  SampledCommand c;
  for (double t = start - kMaxLag; t <= end + kMaxLag; t += step) {
    c.time.push_back(t);
    c.acceleration.push_back(t < 0 ? 0.0 : command.at(t).acceleration[axis]);  // at rest before it starts
  }
  return c;
}

void describe(TableTracking& k) {
  if (!k.delay_significant && !k.gain_significant && !k.left_significant) return;
  k.text = fmt::format("{}: the table did not follow its command: it lags by {:.3g} ms (+- {:.2g}), gain {:.4g} "
                       "(+- {:.2g}); what lag and gain leave is {:.2g} % of the command's RMS (noise {}{:.2g} %)",
                       k.channel, 1e3 * k.delay, 1e3 * k.delay_sd, k.gain, k.gain_sd, 100 * k.left_share,
                       k.noise_stated ? "" : "estimated ", 100 * k.noise_share);
}

TableTracking track_axis(const Recording& recording, const std::vector<double>& recorded, const SampledCommand& c,
                         char axis) {
  TableTracking k;
  k.channel = std::string("table_a") + axis;
  const RecordingChannel* measured = recording.find(k.channel);
  const nlohmann::json noise = recording.nominal.is_object() ? recording.nominal.value("sensor_noise", nlohmann::json::object()) : nlohmann::json::object();
  const double stated = noise.is_object() ? noise.value("acceleration", 0.0) : 0.0;
  k.noise_stated = measured && !measured->derived && stated > 0;  // a derived channel has its own noise
  k.noise = k.noise_stated ? stated : signal::second_difference_noise(recorded);

  comparison::ComparisonParameters p;
  p.noise = k.noise, p.max_lag = kMaxLag;
  const comparison::Aligned a = comparison::align(recording.time, recorded, c.time, c.acceleration);
  const comparison::OffsetGain og = comparison::offset_and_gain(a, c.time, c.acceleration, p);
  k.delay = og.offset, k.gain = og.gain, k.gain_sd = og.gain_sd, k.correlation = og.correlation;
  if (!std::isfinite(k.delay) || !std::isfinite(k.gain)) return k;

  // What lag, gain and bias leave, and the delay's Cramer-Rao bound:
  // var(delay) = noise^2 / sum (gain a'(t_k))^2 for white noise.
  const double h = 0.5 * (c.time[1] - c.time[0]);
  std::vector<double> shifted, left;
  double jerk2 = 0;
  for (std::size_t i = 0; i < a.time.size(); ++i) {
    const double t = a.time[i] - k.delay;
    shifted.push_back(signal::interpolate(c.time, c.acceleration, t));
    left.push_back(a.recorded[i] - k.gain * shifted.back() - og.bias);
    const double slope = (signal::interpolate(c.time, c.acceleration, t + h) -
                          signal::interpolate(c.time, c.acceleration, t - h)) / (2 * h);
    jerk2 += std::pow(k.gain * slope, 2);
  }
  const double command_rms = root_mean_square(shifted);
  k.delay_sd = k.noise / std::sqrt(jerk2);
  k.left_share = root_mean_square(left) / command_rms;
  k.noise_share = k.noise / command_rms;

  const double dof = static_cast<double>(left.size()) - 3;  // delay, gain and bias fitted
  const double chi2 = std::pow(root_mean_square(left) / k.noise, 2) * left.size();
  k.delay_significant = std::abs(k.delay) > kSignificance * k.delay_sd;
  k.gain_significant = std::abs(k.gain - 1) > kSignificance * k.gain_sd;
  k.left_significant = chi2 > dof + kSignificance * std::sqrt(2 * dof);  // chi-square's mean + 4 s.d.
  describe(k);
  return k;
}

}  // namespace

std::vector<TableTracking> table_tracking(const Recording& recording, const ShakeTable& command) {
  std::vector<TableTracking> out;
  if (recording.time.size() < 8) return out;
  const double step = signal::median_step(recording.time) / 8;
  for (int axis = kAxisX; axis <= kAxisZ; ++axis) {
    const char name = static_cast<char>('x' + axis);
    const std::vector<double>* recorded = recording.table_channel('a', name);
    if (!recorded) continue;
    const SampledCommand c = sample_command(command, axis, recording.time.front(), recording.time.back(), step);
    bool commanded = false;
    for (double v : c.acceleration) commanded = commanded || v != 0;
    if (commanded) out.push_back(track_axis(recording, *recorded, c, name));
  }
  return out;
}

}  // namespace freestand
