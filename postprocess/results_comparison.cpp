#include "results_comparison.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "freestand/body_channels.h"
#include "freestand/input_error.h"

namespace freestand {

using comparison::ChannelComparison;
using nlohmann::json;

RunComparison compare_run(const std::vector<AnalysedBody>& simulated, const Recording& recording,
                          const std::string& results_path) {
  std::vector<std::string> simulated_names;
  for (const AnalysedBody& b : simulated) simulated_names.push_back(b.name);
  for (const std::string& name : recording.body_names())
    if (std::find(simulated_names.begin(), simulated_names.end(), name) == simulated_names.end())
      throw InputError(fmt::format("{}: body '{}' is not in the results {} (bodies: {})", recording.path, name,
                                   results_path, fmt::join(simulated_names, ", ")));
  RunComparison run;
  run.parameters = parameters_for(recording.nominal);
  std::vector<AnalysedBody> recorded = analyse_recording(recording);
  for (const AnalysedBody& sim : simulated) {
    const auto rec = std::find_if(recorded.begin(), recorded.end(), [&](const AnalysedBody& r) { return r.name == sim.name; });
    if (rec == recorded.end()) {
      run.unrecorded.push_back(sim.name);
      continue;
    }
    comparison::BodyComparison c = comparison::compare_body(rec->motion, sim.motion, sim.geometry, run.parameters);
    run.bodies.push_back({sim, std::move(*rec), std::move(c)});
  }
  return run;
}

const std::vector<Metric>& error_metrics() {
  static const std::vector<Metric> metrics{
      {"peak_error_percent", "peak error", false, "%", [](const ChannelComparison& c) { return c.peak_error_percent; }},
      {"residual_difference", "residual diff.", true, "", [](const ChannelComparison& c) { return c.residual_difference; }},
      {"nrmse", "NRMSE", false, "", [](const ChannelComparison& c) { return c.nrmse; }},
      {"dominant_frequency_simulated", "f sim", false, "Hz",
       [](const ChannelComparison& c) { return c.spectrum_simulated.dominant_frequency; }},
      {"dominant_frequency_recorded", "f rec", false, "Hz",
       [](const ChannelComparison& c) { return c.spectrum_recorded.dominant_frequency; }},
      {"divergence_time", "diverges at", false, "s", [](const ChannelComparison& c) { return c.divergence_time; }},
      {"time_offset", "time offset", false, "s", [](const ChannelComparison& c) { return c.offset_gain.offset; }},
      {"gain", "gain", false, "", [](const ChannelComparison& c) { return c.offset_gain.gain; }},
      {"correlation", "correlation", false, "", [](const ChannelComparison& c) { return c.offset_gain.correlation; }},
  };
  return metrics;
}

bool channel_moved(const AnalysedBody& body, int channel, const analysis::AnalysisParameters& p) {
  const double noise = channel <= analysis::kTwist ? p.angle_noise : p.length_noise;
  const double peak = body.summary.peaks[channel].magnitude();
  return !body.motion.channels[channel].empty() && std::isfinite(peak) && peak > p.threshold_sigmas * noise;
}

bool channel_moved(const ComparedBody& body, int channel, const analysis::AnalysisParameters& p) {
  return channel_moved(body.simulated, channel, p) || channel_moved(body.recorded, channel, p);
}

int first_divergence(const comparison::BodyComparison& comparison) {
  int first = -1;
  for (int c = 0; c < analysis::kChannelCount; ++c) {
    const double t = comparison.channels[c].divergence_time;
    if (comparison.channels[c].samples > 0 && std::isfinite(t) &&
        (first < 0 || t < comparison.channels[first].divergence_time))
      first = c;
  }
  return first;
}

namespace {

json channel_json(const ChannelComparison& c) {
  json out = {{"samples", c.samples},
              {"peak_recorded", c.peak_recorded},
              {"peak_simulated", c.peak_simulated},
              {"residual_recorded", c.residual_recorded},
              {"residual_simulated", c.residual_simulated},
              {"divergence_threshold", c.divergence_threshold},
              {"centroid_frequency_simulated", c.spectrum_simulated.centroid},
              {"centroid_frequency_recorded", c.spectrum_recorded.centroid},
              {"gain_sd", c.offset_gain.gain_sd},
              {"bias", c.offset_gain.bias}};
  for (const Metric& m : error_metrics()) out[m.key] = m.value(c);
  return out;
}

}  // namespace

json comparison_json(const RunComparison& run) {
  json bodies = json::array();
  const auto& names = channel_names();
  for (const ComparedBody& b : run.bodies) {
    json channels = json::object();
    for (int c = 0; c < analysis::kChannelCount; ++c)
      if (b.comparison.channels[c].samples > 0) channels[names[c]] = channel_json(b.comparison.channels[c]);
    json decay = json::object();
    for (int axis = 0; axis < 2; ++axis) {
      const comparison::ImpactDecay& d = b.comparison.decay[axis];
      decay[names[axis]] = {{"recorded_ratios", d.recorded_ratios},
                            {"simulated_ratios", d.simulated_ratios},
                            {"recorded_amplitudes", d.recorded_amplitudes},
                            {"simulated_amplitudes", d.simulated_amplitudes},
                            {"recorded_median", d.recorded_median},
                            {"simulated_median", d.simulated_median},
                            {"housner_ratio", b.simulated.geometry.known(axis)
                                                  ? b.simulated.geometry.housner_ratio(axis)
                                                  : analysis::kNaN}};
    }
    const int first = first_divergence(b.comparison);
    bodies.push_back({{"name", b.simulated.name},
                      {"channels", channels},
                      {"impact_decay", decay},
                      {"first_divergence", first < 0 ? json(nullptr)
                                                      : json{{"channel", names[first]},
                                                             {"time", b.comparison.channels[first].divergence_time}}}});
  }
  return {{"bodies", bodies},
          {"not_recorded", run.unrecorded},
          {"noise", {{"angle", run.parameters.angle_noise}, {"length", run.parameters.length_noise}}},
          {"units", "SI: rad for rock_x, rock_y, twist; m for slide_x, slide_y, uplift; s; Hz"}};
}

}  // namespace freestand
