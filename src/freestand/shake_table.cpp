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
  // An acceleration given as VALUE UNIT, converted to m/s^2.
  double acceleration(const std::string& what) {
    const double value = number(what);
    const std::string name = next(what + " unit");
    const auto unit = find_motion_unit(name);
    if (!unit || unit->is_velocity)
      throw InputError(fmt::format(
          "fix shaketable: '{}' unit must be g, m/s^2, cm/s^2 or mm/s^2, got '{}'", what, name));
    return value * unit->to_si;
  }

 private:
  const std::vector<std::string>& args_;  // the fix arguments
  std::size_t i_ = 0;                     // next token to read
};

const std::set<std::string> kAnalyticKinds = {"sine", "onesine", "ricker", "rectangle", "sweep"};

int axis_index(const std::string& token) {
  if (token == "x") return 0;
  if (token == "y") return 1;
  if (token == "z") return 2;
  return -1;
}

// Reads one axis option; returns false if the keyword is not an axis option.
bool parse_axis_option(const std::string& key, ArgCursor& in, AxisSpec& axis) {
  if (key == "units") axis.record.units = in.next(key);
  else if (key == "format") axis.record.format = in.next(key);
  else if (key == "column") axis.record.column = in.next(key);
  else if (key == "differentiate") axis.differentiate = in.yes_no(key);
  else if (key == "scale") axis.shaping.scale = in.number(key);
  else if (key == "pga") axis.shaping.target_pga = in.acceleration(key);
  else if (key == "skip") axis.shaping.skip = in.number(key);
  else if (key == "duration") axis.shaping.duration = axis.analytic.duration = in.number(key);
  else if (key == "baseline") axis.shaping.baseline_correct = in.yes_no(key);
  else if (key == "amplitude") axis.analytic.amplitude = in.acceleration(key);
  else if (key == "frequency") axis.analytic.frequency = in.number(key);
  else if (key == "frequency_end") axis.analytic.frequency_end = in.number(key);
  else if (key == "width") axis.analytic.width = in.number(key);
  else return false;
  return true;
}

void check_axis(const AxisSpec& axis, const char* name) {
  if (axis.from_record && axis.record.units.empty())
    throw InputError(fmt::format(
        "fix shaketable: axis {} record '{}' needs 'units' (g, m/s^2, cm/s^2, mm/s^2, m/s, cm/s): "
        "units are never guessed", name, axis.record.path));
  if (!axis.from_record && (axis.record.units.size() || axis.differentiate))
    throw InputError(fmt::format(
        "fix shaketable: axis {}: 'units'/'differentiate' apply to records only", name));
}

}  // namespace

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
          "fix shaketable: '{}' before any axis; start with 'x', 'y' or 'z'", key));
    } else if (!parse_axis_option(key, in, *axis)) {
      throw InputError(fmt::format("fix shaketable: unknown keyword '{}'", key));
    }
  }
  bool any = false;
  for (int i = 0; i < 3; ++i) {
    if (!spec.axes[i].active) continue;
    any = true;
    check_axis(spec.axes[i], i == 0 ? "x" : i == 1 ? "y" : "z");
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
  for (int i = 0; i < 3; ++i) {
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
  for (int i = 0; i < 3; ++i) {
    if (!axes_[i]) continue;
    const AxisState s = axes_[i]->at(t);
    state.acceleration[i] = s.acceleration;
    state.velocity[i] = s.velocity;
    state.displacement[i] = s.displacement;
  }
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
  const char* names[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    if (!axes_[i]) continue;
    lines.push_back(fmt::format("axis {}: {}, peak {:.4g} m/s^2 ({:.4g} g), duration {:.4g} s",
                                names[i], sources_[i], axes_[i]->peak_acceleration(),
                                axes_[i]->peak_acceleration() / kStandardGravity,
                                axes_[i]->duration()));
  }
  return lines;
}

}  // namespace freestand
