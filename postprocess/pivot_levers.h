#ifndef FREESTAND_PIVOT_LEVERS_H
#define FREESTAND_PIVOT_LEVERS_H

// The lever arms of a body rocking on its base edges, read from its rock angles and uplift.
//
// A rigid body tilted by theta about a base edge lifts its centre of mass by
//   u = b sin|theta| - h (1 - cos theta),
// b the horizontal distance from that edge (the pivot) to the centre of mass and h the centre's
// height over the base. That is kinematics: chaos reshuffles when and how far a body rocks, not
// where it pivots. b sets the side's uplift threshold (g b / h) and its restoring moment; an
// inset or crushed edge shortens both sides' b, a centre of mass off the axis one side's and
// lengthens the other's, a soft contact sinks the pivot under load (docs/diagnose.md, features).

#include <Eigen/Core>
#include <vector>

namespace freestand::diagnosis {

struct PivotLevers {
  Eigen::Matrix2d lever;  // m: [axis (0 rock_x, 1 rock_y)][side (0 leaning to +, 1 to -)]; NaN: side not fitted
  Eigen::Matrix2d sd;     // m: their s.d. from the length noise; NaN where not fitted
  Eigen::Matrix2d onset;  // s: when the body first leaned to that side beyond the fitting tilt
};

// Least squares of `uplift` on sin theta for each side of each rocking axis the body leans to
// beyond `min_tilt` (rad) for at least `min_time` (s) in all, beside a constant, a drift in time
// and, when given, the table's travel (an offset, a sensor drift, a carry by a table moving
// vertically: rest_slopes in diagnosis.cpp). The centre's `height` h is the stated geometry's (no
// candidate moves it; fitted it shares the levers' information, as 1 - cos theta_x cos theta_y
// rises with sin|theta|: 2.4 times their s.d. in the test), or fitted where NaN. Over the samples `use`
// marks (the body not in flight, what supports it at rest) with every channel finite. `rock_x` or
// `rock_y` may be null (not recorded). `noise`: the uplift's s.d.
PivotLevers pivot_levers(const std::vector<double>& time, const std::vector<double>* rock_x,
                         const std::vector<double>* rock_y, const std::vector<double>& uplift,
                         const std::vector<double>* travel, const std::vector<bool>& use, double height,
                         double min_tilt, double min_time, double noise);

}  // namespace freestand::diagnosis

#endif
