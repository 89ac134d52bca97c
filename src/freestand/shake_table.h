#ifndef FREESTAND_SHAKE_TABLE_H
#define FREESTAND_SHAKE_TABLE_H

// A shake table: up to three translational axes, each driven by a recorded
// ground motion or a built-in analytic motion, played from a start time.
// This is the LIGGGHTS-free core of `fix shaketable`; its argument grammar
// is documented in docs/fix_shaketable.md.

#include <Eigen/Core>
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

// Everything `fix shaketable` was told.
struct ShakeTableSpec {
  std::array<AxisSpec, 3> axes;   // x, y, z
  bool start_given = false;       // true when `start` was given
  double start = 0.0;             // simulation time at which motion time 0 is played (s)
};

// Parses the fix arguments after the style name. Throws InputError naming
// the keyword that is wrong, missing or out of place.
ShakeTableSpec parse_shake_table_args(const std::vector<std::string>& args);

// Table kinematics at one instant, world frame.
struct TableState {
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  // m/s^2
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // m/s
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // m, from the rest position
};

class ShakeTable {
 public:
  // Reads the records; throws InputError on bad files or parameters.
  explicit ShakeTable(const ShakeTableSpec& spec);
  // State at motion time t (t = simulation time - start).
  TableState at(double t) const;
  // Longest axis duration (s).
  double duration() const;
  // One line per moving axis: source, peak acceleration, duration.
  std::vector<std::string> describe() const;

 private:
  std::array<std::unique_ptr<AxisMotion>, 3> axes_;  // null: axis at rest
  std::array<std::string, 3> sources_;               // what drives each axis, for describe()
};

}  // namespace freestand

#endif
