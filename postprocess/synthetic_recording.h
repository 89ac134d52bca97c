#ifndef FREESTAND_POST_SYNTHETIC_RECORDING_H
#define FREESTAND_POST_SYNTHETIC_RECORDING_H

// Recordings made by the simulator with known contact parameters plus
// measurement noise, to prove that `freestand calibrate` finds the parameters
// again (docs/calibration.md).

#include <nlohmann/json.hpp>

#include <string>

#include "recording.h"

namespace freestand {

struct MeasurementNoise {
  double angle = 0.0;   // standard deviation on rock_x, rock_y, twist (rad)
  double length = 0.0;  // on slide_x, slide_y, uplift and the centre x, y, z (m)
  unsigned seed = 1;
  double gain_sd = 0.0; // relative s.d. of each body channel's gain (its calibration), drawn per channel
};

// Adds Gaussian noise to the body channels of `recording` (angles: rock,
// twist; lengths: slide, uplift, centre), each first scaled by its own gain
// 1 + N(0, gain_sd^2); table channels and quaternions are left exact.
void add_measurement_noise(Recording& recording, const MeasurementNoise& noise);

// Runs the scenario `document` (the known parameters in its interfaces and
// `contact`) in `directory` and returns its results as a recording with
// Gaussian noise on the body channels; the table channels are exact (the
// table's motion is the input). The nominal keeps bodies and interfaces but
// not the contact parameters (stiffness, restitution, friction), which a
// calibration has to find, and states the noise as sensor_noise.
Recording synthetic_recording(const nlohmann::json& document, const std::string& directory,
                              const MeasurementNoise& noise);

}  // namespace freestand

#endif
