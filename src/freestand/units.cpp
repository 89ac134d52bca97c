#include "freestand/units.h"

namespace freestand {

std::optional<MotionUnit> find_motion_unit(std::string_view name) {
  static constexpr MotionUnit kUnits[] = {
      {"g", kStandardGravity, false}, {"m/s^2", 1.0, false}, {"cm/s^2", 1e-2, false},
      {"mm/s^2", 1e-3, false},        {"m/s", 1.0, true},    {"cm/s", 1e-2, true},
      {"rad/s^2", 1.0, false, true},  {"rad/s", 1.0, true, true},
  };
  for (const MotionUnit& unit : kUnits)
    if (unit.name == name) return unit;
  return std::nullopt;
}

}  // namespace freestand
