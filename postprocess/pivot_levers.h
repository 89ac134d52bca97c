#ifndef FREESTAND_PIVOT_LEVERS_H
#define FREESTAND_PIVOT_LEVERS_H

// The lever arms of a body rocking on its base edges, read from its rock angles and uplift.
//
// A rigid body tilted by theta about a base edge lifts its centre of mass by
//   u = b sin|theta| - h (1 - cos theta) + s sqrt|sin theta|,
// b the horizontal distance from that edge (the pivot) to the centre of mass and h the centre's
// height over the base. That is kinematics: chaos reshuffles when and how far a body rocks, not
// where it pivots. b sets the side's uplift threshold (g b / h) and its restoring moment; an
// inset or crushed edge shortens both sides' b, a centre of mass off the axis one side's and
// lengthens the other's. s (< 0) is the pivot's sink into a compliant contact: on a Winkler
// base of modulus k (N/m^3) and depth D across the axis, carrying the weight W, the contact
// shrinks to c = sqrt(2 W / (k D theta)) from the edge, whose depth theta c gives
// s = -sqrt(2 W / (k D)). A soft contact is thus told from an inset edge: fitted without s, it
// reads as a shorter b (a tower on a joint 18 times soft: 0.27 m for 0.36, 0.35 with s), which
// the inset also gives, but fitted beside the sqrt the levers lose precision (their s.d. x 3 in
// the test), which told an off-axis centre of mass from an inset. So the levers are fitted
// without s, as before, and s in a second fit beside them, as a feature of its own (study 38).

#include <Eigen/Core>
#include <vector>

namespace freestand::diagnosis {

struct PivotLevers {
  Eigen::Matrix2d lever;  // m: [axis (0 rock_x, 1 rock_y)][side (0 leaning to +, 1 to -)]; NaN: side not fitted
  Eigen::Matrix2d sd;     // m: their s.d. from the length noise; NaN where not fitted
  Eigen::Matrix2d onset;  // s: when the body first leaned to that side beyond the fitting tilt
  double sink;            // m per sqrt(rad): s, the pivot's sink with the tilt (<= 0), fitted beside the levers;
                          // NaN: no side fitted
  double sink_sd;         // m per sqrt(rad): its s.d. from the length noise
};

// Least squares of `uplift` on sin theta for each side of each rocking axis the body leans to
// beyond `min_tilt` (rad) for at least `min_time` (s) in all (and again with the square root of
// the tilt, the magnitude of both axes' sines, for the sink), beside a constant, a drift in time
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
