#include "freestand/shake_table.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <set>

#include "freestand/input_error.h"
#include "freestand/units.h"

namespace freestand {
namespace {

class ArgCursor {
 public:
  explicit ArgCursor(const std::vector<std::string>& args) : args_(args) {}
  bool done() const { return i_ >= args_.size(); }
  const std::string& peek() const { return args_[i_]; }
  std::string next(const std::string& what) {
    if (done()) throw InputError(fmt::format("fix shaketable: '{}' needs a value", what));
    return args_[i_++];
  }
  double number(const std::string& what) {
    const std::string token = next(what);
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(value))
      throw InputError(fmt::format("fix shaketable: '{}' expects a number, got '{}'", what, token));
    return value;
  }
  bool yes_no(const std::string& what) {
    const std::string token = next(what);
    if (token == "yes") return true;
    if (token == "no") return false;
    throw InputError(fmt::format("fix shaketable: '{}' expects yes or no, got '{}'", what, token));
  }
  // An acceleration given as VALUE UNIT, converted to SI: m/s^2, or rad/s^2
  // for a rotational axis.
  double acceleration(const std::string& what, bool angular) {
    const double value = number(what);
    const std::string name = next(what + " unit");
    const auto unit = find_motion_unit(name);
    if (!unit || unit->is_velocity || unit->is_angular != angular)
      throw InputError(fmt::format("fix shaketable: '{}' unit must be {}, got '{}'", what,
                                   angular ? "rad/s^2" : "g, m/s^2, cm/s^2 or mm/s^2", name));
    return value * unit->to_si;
  }

 private:
  const std::vector<std::string>& args_;  // the fix arguments
  std::size_t i_ = 0;                     // next token to read
};

const std::set<std::string> kAnalyticKinds = {"sine", "onesine", "ricker", "rectangle", "sweep"};

int axis_index(const std::string& token) {
  for (int i = 0; i < kTableAxes; ++i)
    if (token == table_axis_name(i)) return i;
  return -1;
}

// Reads one axis option; returns false if the keyword is not an axis option.
bool parse_axis_option(const std::string& key, ArgCursor& in, AxisSpec& axis, bool angular) {
  if (key == "units") axis.record.units = in.next(key);
  else if (key == "format") axis.record.format = in.next(key);
  else if (key == "column") axis.record.column = in.next(key);
  else if (key == "differentiate") axis.differentiate = in.yes_no(key);
  else if (key == "scale") axis.shaping.scale = in.number(key);
  else if (key == "pga") axis.shaping.target_pga = in.acceleration(key, angular);
  else if (key == "skip") axis.shaping.skip = in.number(key);
  else if (key == "duration") axis.shaping.duration = axis.analytic.duration = in.number(key);
  else if (key == "baseline") axis.shaping.baseline_correct = in.yes_no(key);
  else if (key == "amplitude") axis.analytic.amplitude = in.acceleration(key, angular);
  else if (key == "frequency") axis.analytic.frequency = in.number(key);
  else if (key == "frequency_end") axis.analytic.frequency_end = in.number(key);
  else if (key == "width") axis.analytic.width = in.number(key);
  else return false;
  return true;
}

void check_axis(const AxisSpec& axis, int index) {
  const char* name = table_axis_name(index);
  const bool angular = is_rotational(index);
  if (axis.from_record && axis.record.units.empty())
    throw InputError(fmt::format(
        "fix shaketable: axis {} record '{}' needs 'units' ({}): units are never guessed", name,
        axis.record.path, angular ? "rad/s^2, rad/s" : "g, m/s^2, cm/s^2, mm/s^2, m/s, cm/s"));
  const auto unit = find_motion_unit(axis.record.units);
  if (axis.from_record && unit && unit->is_angular != angular)
    throw InputError(fmt::format("fix shaketable: axis {} record '{}': units '{}' are {}", name,
                                 axis.record.path, axis.record.units,
                                 angular ? "not angular (rad/s^2, rad/s)"
                                         : "angular: only roll and pitch rotate"));
  if (!axis.from_record && (axis.record.units.size() || axis.differentiate))
    throw InputError(fmt::format(
        "fix shaketable: axis {}: 'units'/'differentiate' apply to records only", name));
}

}  // namespace

const char* table_axis_name(int axis) {
  static const char* const names[kTableAxes] = {"x", "y", "z", "roll", "pitch"};
  return names[axis];
}

ShakeTableSpec parse_shake_table_args(const std::vector<std::string>& args) {
  ShakeTableSpec spec;
  ArgCursor in(args);
  AxisSpec* axis = nullptr;
  while (!in.done()) {
    const std::string key = in.next("keyword");
    const int index = axis_index(key);
    if (index >= 0) {
      axis = &spec.axes[index];
      if (axis->active) throw InputError(fmt::format("fix shaketable: axis {} given twice", key));
      axis->active = true;
      const std::string source = in.next(key);
      if (source == "record") {
        axis->from_record = true;
        axis->record.path = in.next("record");
      } else if (kAnalyticKinds.count(source)) {
        axis->analytic.kind = source;
      } else {
        throw InputError(fmt::format(
            "fix shaketable: axis {} source must be 'record FILE' or one of sine, onesine, "
            "ricker, rectangle, sweep; got '{}'", key, source));
      }
    } else if (key == "start") {
      spec.start_given = true;
      spec.start = in.number(key);
    } else if (!axis) {
      throw InputError(fmt::format(
          "fix shaketable: '{}' before any axis; start with 'x', 'y', 'z', 'roll' or 'pitch'", key));
    } else if (!parse_axis_option(key, in, *axis, is_rotational(axis - spec.axes.data()))) {
      throw InputError(fmt::format("fix shaketable: unknown keyword '{}'", key));
    }
  }
  bool any = false;
  for (int i = 0; i < kTableAxes; ++i) {
    if (!spec.axes[i].active) continue;
    any = true;
    check_axis(spec.axes[i], i);
  }
  if (!any) throw InputError("fix shaketable: no axis given (e.g. 'x record FILE units g')");
  return spec;
}

namespace {

std::unique_ptr<AxisMotion> make_record_motion(const AxisSpec& axis) {
  GroundRecord record = read_ground_record(axis.record);
  if (record.is_velocity && !axis.differentiate)
    throw InputError(fmt::format(
        "fix shaketable: {} is a velocity record (units {}); add 'differentiate yes' to play "
        "its derivative as the table acceleration", record.source, axis.record.units));
  if (!record.is_velocity && axis.differentiate)
    throw InputError(fmt::format(
        "fix shaketable: 'differentiate yes' but {} is an acceleration record (units {})",
        record.source, axis.record.units));
  std::vector<double> a = record.is_velocity ? differentiate(record.t, record.value) : record.value;
  return shape_record(record.t, a, axis.shaping);
}

}  // namespace

ShakeTable::ShakeTable(const ShakeTableSpec& spec) {
  for (int i = 0; i < kTableAxes; ++i) {
    const AxisSpec& axis = spec.axes[i];
    if (!axis.active) continue;
    if (axis.from_record) {
      axes_[i] = make_record_motion(axis);
      sources_[i] = fmt::format("record {} ({})", axis.record.path, axis.record.units);
    } else {
      axes_[i] = make_analytic_motion(axis.analytic);
      sources_[i] = fmt::format("{} motion", axis.analytic.kind);
    }
  }
}

TableState ShakeTable::at(double t) const {
  TableState state;
  for (int i = 0; i < kAxisRoll; ++i) {
    if (!axes_[i]) continue;
    const AxisState s = axes_[i]->at(t);
    state.acceleration[i] = s.acceleration;
    state.velocity[i] = s.velocity;
    state.displacement[i] = s.displacement;
  }
  if (!rotates()) return state;
  const AxisState roll = axes_[kAxisRoll] ? axes_[kAxisRoll]->at(t) : AxisState{};
  const AxisState pitch = axes_[kAxisPitch] ? axes_[kAxisPitch]->at(t) : AxisState{};
  // R = R_y(pitch) R_x(roll): roll turns the table about its own x axis,
  // which pitch then turns about the world y axis.
  const Eigen::AngleAxisd pitch_rotation(pitch.displacement, Eigen::Vector3d::UnitY());
  state.roll = roll.displacement;
  state.pitch = pitch.displacement;
  state.orientation = pitch_rotation * Eigen::AngleAxisd(roll.displacement, Eigen::Vector3d::UnitX());
  const Eigen::Vector3d roll_axis = pitch_rotation * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d pitch_rate = pitch.velocity * Eigen::Vector3d::UnitY();
  state.angular_velocity = pitch_rate + roll.velocity * roll_axis;
  // d/dt of roll_axis is pitch_rate x roll_axis.
  state.angular_acceleration = pitch.acceleration * Eigen::Vector3d::UnitY() +
                               roll.acceleration * roll_axis +
                               roll.velocity * pitch_rate.cross(roll_axis);
  return state;
}

double ShakeTable::duration() const {
  double longest = 0.0;
  for (const auto& axis : axes_)
    if (axis) longest = std::max(longest, axis->duration());
  return longest;
}

std::vector<std::string> ShakeTable::describe() const {
  std::vector<std::string> lines;
  for (int i = 0; i < kTableAxes; ++i) {
    if (!axes_[i]) continue;
    const double peak = axes_[i]->peak_acceleration();
    lines.push_back(is_rotational(i)
                        ? fmt::format("axis {}: {}, peak {:.4g} rad/s^2, duration {:.4g} s",
                                      table_axis_name(i), sources_[i], peak, axes_[i]->duration())
                        : fmt::format("axis {}: {}, peak {:.4g} m/s^2 ({:.4g} g), duration {:.4g} s",
                                      table_axis_name(i), sources_[i], peak,
                                      peak / kStandardGravity, axes_[i]->duration()));
  }
  return lines;
}

}  // namespace freestand
