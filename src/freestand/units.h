#ifndef FREESTAND_UNITS_H
#define FREESTAND_UNITS_H

// Units that users state for ground motion (never guessed).

#include <optional>
#include <string_view>

namespace freestand {

// Standard acceleration of gravity g_n, m/s^2 (exact by definition, CGPM 1901).
// PEER AT2 files are "in units of g"; some tools use 9.81 instead (0.03 % more).
inline constexpr double kStandardGravity = 9.80665;

// A unit of a ground-motion value.
struct MotionUnit {
  std::string_view name;  // as the user writes it: "g", "m/s^2", "cm/s^2", "mm/s^2", "m/s", "cm/s",
                          // or for a rotational table axis "rad/s^2", "rad/s"
  double to_si;           // SI value of one unit (m/s^2, m/s, rad/s^2 or rad/s)
  bool is_velocity;       // a velocity unit rather than an acceleration unit
  bool is_angular = false;  // rad/s^2 or rad/s: for the table's rotational axes (pitch, roll)
};

// The unit called `name`, or nothing if there is no such unit.
std::optional<MotionUnit> find_motion_unit(std::string_view name);

}  // namespace freestand

#endif
