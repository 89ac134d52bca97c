#include "pivot_levers.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "signal_tools.h"

namespace freestand::diagnosis {

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Side {
  int axis, side;  // as PivotLevers' indices
  double onset;    // s: first lean beyond the fitting tilt
};

// theta leaning to `side` (0: +, 1: -) by more than `tilt`.
bool leans(double theta, int side, double tilt) { return side == 0 ? theta > tilt : theta < -tilt; }

}  // namespace

PivotLevers pivot_levers(const std::vector<double>& time, const std::vector<double>* rock_x,
                         const std::vector<double>* rock_y, const std::vector<double>& uplift,
                         const std::vector<double>* travel, const std::vector<bool>& use, double height,
                         double min_tilt, double min_time, double noise) {
  PivotLevers out{Eigen::Matrix2d::Constant(kNaN), Eigen::Matrix2d::Constant(kNaN), Eigen::Matrix2d::Constant(kNaN), kNaN,
                  kNaN};
  const std::vector<double>* rock[2] = {rock_x, rock_y};
  const auto theta = [&](int axis, std::size_t k) { return rock[axis] ? (*rock[axis])[k] : 0.0; };
  std::vector<std::size_t> rows;
  for (std::size_t k = 0; k < time.size(); ++k)
    if (use[k] && std::isfinite(uplift[k]) && std::isfinite(theta(0, k)) && std::isfinite(theta(1, k)) &&
        (!travel || std::isfinite((*travel)[k])))
      rows.push_back(k);
  if (rows.empty()) return out;

  // The sides leaned to long enough to fit; samples leaning beyond the tilt to any other side
  // are left out (their uplift has no lever in the fit).
  const double dt = signal::median_step(time);
  std::vector<Side> sides;
  bool fitted[2][2] = {};
  for (int axis : {0, 1})
    for (int side : {0, 1}) {
      if (!rock[axis]) continue;
      double onset = kNaN;
      std::size_t n = 0;
      for (std::size_t k : rows)
        if (leans(theta(axis, k), side, min_tilt)) ++n, onset = std::isnan(onset) ? time[k] : onset;
      if (n * dt >= min_time) sides.push_back({axis, side, onset}), fitted[axis][side] = true;
    }
  if (sides.empty()) return out;
  std::vector<std::size_t> kept;
  for (std::size_t k : rows) {
    bool unfitted_lean = false;
    for (int axis : {0, 1})
      for (int side : {0, 1}) unfitted_lean |= !fitted[axis][side] && leans(theta(axis, k), side, min_tilt);
    if (!unfitted_lean) kept.push_back(k);
  }

  // Columns: the levers, a constant, time, the travel, the height where it is not given, and
  // last the sink, fitted beside the rest for its own value only (see the header).
  const bool fit_height = !std::isfinite(height);
  const Eigen::Index nl = static_cast<Eigen::Index>(sides.size()), m = nl + 3 + (travel ? 1 : 0) + (fit_height ? 1 : 0);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(kept.size()), m);
  Eigen::VectorXd u(a.rows());
  for (Eigen::Index i = 0; i < a.rows(); ++i) {
    const std::size_t k = kept[static_cast<std::size_t>(i)];
    for (Eigen::Index j = 0; j < nl; ++j) {
      const Side& s = sides[static_cast<std::size_t>(j)];
      const double t = theta(s.axis, k);
      a(i, j) = (s.side == 0 ? t > 0 : t < 0) ? std::abs(std::sin(t)) : 0.0;
    }
    const double drop = 1 - std::cos(theta(0, k)) * std::cos(theta(1, k));  // the centre's fall per m of height
    a(i, nl) = 1, a(i, nl + 1) = time[k] - time[kept.front()];
    if (travel) a(i, nl + 2) = (*travel)[k];
    if (fit_height) a(i, m - 2) = -drop;
    a(i, m - 1) = std::sqrt(std::hypot(std::sin(theta(0, k)), std::sin(theta(1, k))));
    u(i) = uplift[k] + (fit_height ? 0.0 : height * drop);
  }
  const auto fit = [&](Eigen::Index columns) -> std::optional<std::pair<Eigen::VectorXd, Eigen::VectorXd>> {
    const auto x = a.leftCols(columns);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(x.transpose() * x);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all()) return std::nullopt;
    return std::make_pair(ldlt.solve(x.transpose() * u),
                          ldlt.solve(Eigen::MatrixXd::Identity(columns, columns)).diagonal() * noise * noise);
  };
  const auto rigid = fit(m - 1);
  if (!rigid) return out;
  for (Eigen::Index j = 0; j < nl; ++j) {
    const Side& s = sides[static_cast<std::size_t>(j)];
    out.lever(s.axis, s.side) = rigid->first(j), out.sd(s.axis, s.side) = std::sqrt(rigid->second(j));
    out.onset(s.axis, s.side) = s.onset;
  }
  if (const auto sinking = fit(m)) out.sink = sinking->first(m - 1), out.sink_sd = std::sqrt(sinking->second(m - 1));
  return out;
}

}  // namespace freestand::diagnosis
