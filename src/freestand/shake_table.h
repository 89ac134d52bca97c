#ifndef FREESTAND_SHAKE_TABLE_H
#define FREESTAND_SHAKE_TABLE_H

// A shake table: up to three translational axes and two rotational ones
// (roll about x, pitch about y), each driven by a recorded ground motion or a
// built-in analytic motion, played from a start time.
// This is the LIGGGHTS-free core of `fix shaketable`; its argument grammar
// is documented in docs/fix_shaketable.md.

#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "freestand/ground_motion_reader.h"
#include "freestand/table_motion.h"

namespace freestand {

// How one axis moves, as written in the input script.
struct AxisSpec {
  bool active = false;            // false: the axis does not move
  bool from_record = false;       // true: `record FILE`; false: analytic
  RecordSource record;            // file, format, column, units (from_record)
  bool differentiate = false;     // play the derivative of a velocity record
  RecordShaping shaping;          // scale/pga, skip, duration, baseline
  AnalyticMotionSpec analytic;    // kind and parameters (!from_record)
};

// Table axes in ShakeTableSpec::axes: translations along x, y, z (m/s^2),
// then rotations roll (about x) and pitch (about y) (rad/s^2).
enum TableAxis { kAxisX, kAxisY, kAxisZ, kAxisRoll, kAxisPitch, kTableAxes };
const char* table_axis_name(int axis);
inline bool is_rotational(int axis) { return axis >= kAxisRoll; }

// Everything `fix shaketable` was told.
struct ShakeTableSpec {
  std::array<AxisSpec, kTableAxes> axes;   // by TableAxis
  bool start_given = false;       // true when `start` was given
  double start = 0.0;             // simulation time at which motion time 0 is played (s)
};

// Parses the fix arguments after the style name. Throws InputError naming
// the keyword that is wrong, missing or out of place.
ShakeTableSpec parse_shake_table_args(const std::vector<std::string>& args);

// Table kinematics at one instant, world frame. The table rotates about its
// reference point (the centre of its top at rest, moved by `displacement`):
// orientation = R_y(pitch) R_x(roll), so the angular velocity is
//   omega = pitch' e_y + roll' R_y(pitch) e_x
// and a table point at rest position p is at c + d + R (p - c), c the
// reference point at rest (docs/fix_shaketable.md, "Rotation").
struct TableState {
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  // m/s^2
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // m/s
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // m, from the rest position
  double roll = 0.0, pitch = 0.0;                          // rad
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // table frame -> world
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();       // rad/s, world
  Eigen::Vector3d angular_acceleration = Eigen::Vector3d::Zero();   // rad/s^2, world
};

class ShakeTable {
 public:
  // Reads the records; throws InputError on bad files or parameters.
  explicit ShakeTable(const ShakeTableSpec& spec);
  // State at motion time t (t = simulation time - start).
  TableState at(double t) const;
  // Longest axis duration (s).
  double duration() const;
  // True when roll or pitch moves.
  bool rotates() const { return axes_[kAxisRoll] || axes_[kAxisPitch]; }
  // One line per moving axis: source, peak acceleration, duration.
  std::vector<std::string> describe() const;

 private:
  std::array<std::unique_ptr<AxisMotion>, kTableAxes> axes_;  // null: axis at rest
  std::array<std::string, kTableAxes> sources_;               // what drives each axis, for describe()
};

}  // namespace freestand

#endif
