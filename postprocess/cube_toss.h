#ifndef FREESTAND_POST_CUBE_TOSS_H
#define FREESTAND_POST_CUBE_TOSS_H

// The DAIR Lab cube tosses (../shared/data/experiments/cube_toss/README.md)
// as recordings: channels of body `cube`, the pose as extension columns and
// a nominal.json in the scene vocabulary, so that a toss can be simulated
// and compared. docs/recordings.md describes the conversion and its caveats.

#include <Eigen/Geometry>

#include <map>
#include <string>
#include <vector>

#include "recording.h"

namespace freestand {

// One tracked sample, as in the file.
struct CubeTossSample {
  int k = 0;                    // sample index within the toss (t = k / 148 s)
  Eigen::Quaterniond orientation;  // tracked body frame -> world
  Eigen::Vector3d centre;       // cube centre, world (m)
  Eigen::Vector3d omega_body;   // angular velocity in the tracked body axes (rad/s)
  Eigen::Vector3d velocity;     // centre velocity, world (m/s)
};

// What the data set's README states about the cube and the rig.
struct CubeTossModel {
  double edge = 0.1048;         // m
  double mass = 0.37;           // kg
  double inertia = 0.00081;     // kg m^2 about each principal axis through the centre
  double mu = 0.15;             // the authors' model friction (not a measurement)
  double sampling_hz = 148.0;   // optical tracking rate
  double table_height = -0.001; // table plane z in the tracking frame (m), "about 1 mm below 0"
  // A sample is in free flight while every corner is this far above the table
  // (m): the table height is known to about 0.3 mm (spread of the resting
  // heights) and the tracked corners to about 0.8 mm (the resting faces tilt by
  // up to 0.6 deg at 74 mm from the centre).
  double flight_clearance = 0.002;
};

// The state of a toss at its first sample, from a least-squares fit of free
// flight to the samples before the cube can touch the table: the centre
// follows x0 + v0 t - g t^2 / 2 e_z, the orientation exp(omega t) R0 (torque-free
// motion of a body with isotropic inertia: the world angular velocity is
// constant). The data set's velocities are backward differences, the velocity
// half a sample (3.4 ms) earlier (vz too high by g / 296 = 0.033 m/s), and
// each rests on two noisy samples.
struct CubeFlightState {
  Eigen::Vector3d centre;          // m, world
  Eigen::Vector3d velocity;        // m/s, world
  Eigen::Quaterniond orientation;  // tracked body frame -> world
  Eigen::Vector3d omega;           // rad/s, world
  int samples = 0;                 // flight samples fitted; 0: fewer than 2, the first sample's values
};
CubeFlightState cube_flight_state(const std::vector<CubeTossSample>& samples, const CubeTossModel& model = {},
                                  double gravity = 9.81);

// Every toss in the gzipped CSV, by toss id, samples in k order. Throws
// InputError naming file and line for a malformed file.
std::map<int, std::vector<CubeTossSample>> read_cube_tosses(const std::string& gz_path);

// Toss `id` as a recording (path left empty). The body frame is the tracked
// frame turned by a symmetry of the cube so that the face the cube rests on
// at the end of the toss is the base (docs/recordings.md). The nominal's
// initial state is cube_flight_state().
Recording cube_toss_recording(int id, const std::vector<CubeTossSample>& samples,
                              const CubeTossModel& model = {});

// Writes tosses first..last of gz_path as out_dir/cube_toss_NNN.{csv,nominal.json}
// (out_dir is created); returns the stems written. Throws InputError for a
// range the file does not hold.
std::vector<std::string> convert_cube_tosses(const std::string& gz_path, const std::string& out_dir,
                                             int first, int last);

}  // namespace freestand

#endif
