#include "synthetic_recording.h"

#include <random>

#include "calibration.h"

namespace freestand {

void add_measurement_noise(Recording& recording, const MeasurementNoise& noise) {
  std::mt19937 generator(noise.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (RecordingChannel& c : recording.channels) {
    const std::string channel = c.name.substr(c.name.rfind('.') + 1);
    if (c.name.rfind("table_", 0) == 0 || channel[0] == 'q') continue;  // table: the input; quaternions: kept unit
    const bool angle = channel == "rock_x" || channel == "rock_y" || channel == "twist";
    // No draw without a gain s.d., so the noise of a given seed stays what it was without gains.
    const double gain = noise.gain_sd > 0 ? 1 + noise.gain_sd * normal(generator) : 1;
    for (double& v : c.values) v = gain * v + (angle ? noise.angle : noise.length) * normal(generator);
  }
}

Recording synthetic_recording(const nlohmann::json& document, const std::string& directory,
                              const MeasurementNoise& noise) {
  Recording recording = run_scenario_document(document, directory);
  add_measurement_noise(recording, noise);
  for (nlohmann::json& f : recording.nominal["interfaces"])
    for (const char* key : {"mu", "mu_s", "mu_k", "restitution", "contact_stiffness", "friction_decay"}) f.erase(key);
  if (noise.angle > 0 && noise.length > 0)  // what the experimenter states about the sensors
    recording.nominal["sensor_noise"] = {{"angle", noise.angle}, {"length", noise.length}};
  recording.nominal["source"] = "synthetic: freestand simulation with known contact parameters plus Gaussian noise";
  recording.nominal["sampling_hz"] = (recording.time.size() - 1) / (recording.time.back() - recording.time.front());
  return recording;
}

}  // namespace freestand
