#include "signal_analysis.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace freestand::validation {

std::vector<std::vector<double>> read_rows(const fs::path& file, std::size_t columns) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> row;
    double value;
    while (fields >> value) row.push_back(value);
    if (row.size() < columns)
      throw std::runtime_error(file.string() + ": short line '" + line + "'");
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<double> column(const std::vector<std::vector<double>>& rows, std::size_t index) {
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& row : rows) out.push_back(row.at(index));
  return out;
}

RockingCycles rocking_cycles(const std::vector<double>& t, const std::vector<double>& theta,
                             double hysteresis) {
  RockingCycles out;
  const std::size_t n = t.size();
  // Sign of the current half-cycle, set once |theta| exceeds the hysteresis.
  int sign = 0;
  double last_crossing = NAN;
  std::vector<std::size_t> starts;  // first sample index of each half-cycle after an impact
  for (std::size_t k = 1; k < n; ++k) {
    if ((theta[k - 1] > 0) != (theta[k] > 0)) {
      // Linear interpolation of the zero crossing.
      last_crossing = t[k - 1] + (t[k] - t[k - 1]) * theta[k - 1] / (theta[k - 1] - theta[k]);
    }
    if (std::fabs(theta[k]) > hysteresis) {
      const int s = theta[k] > 0 ? 1 : -1;
      if (sign != 0 && s != sign && !std::isnan(last_crossing)) {
        out.impacts.push_back(last_crossing);
        starts.push_back(k);
      }
      sign = s;
    }
  }
  // Amplitude between consecutive impacts.
  for (std::size_t i = 0; i + 1 < out.impacts.size(); ++i) {
    std::size_t best = starts[i];
    for (std::size_t k = starts[i]; k < n && t[k] < out.impacts[i + 1]; ++k)
      if (std::fabs(theta[k]) > std::fabs(theta[best])) best = k;
    double peak = std::fabs(theta[best]);
    if (best > 0 && best + 1 < n) {
      // Vertex of the parabola through three equally spaced samples.
      const double a = std::fabs(theta[best - 1]), b = peak, c = std::fabs(theta[best + 1]);
      const double curvature = a - 2 * b + c;
      if (curvature < 0) peak = b - (a - c) * (a - c) / (8 * curvature);
    }
    out.amplitudes.push_back(peak);
  }
  return out;
}

long first_rate_above(const std::vector<double>& t, const std::vector<double>& value,
                      std::size_t window, double direction, double threshold, std::size_t first) {
  for (std::size_t k = std::max(first, window); k < t.size(); ++k) {
    const double rate = (value[k] - value[k - window]) / (t[k] - t[k - window]);
    if (direction * rate > threshold) return static_cast<long>(k);
  }
  return -1;
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double xi) {
  if (xi <= x.front()) return y.front();
  if (xi >= x.back()) return y.back();
  const std::size_t hi = std::lower_bound(x.begin(), x.end(), xi) - x.begin();
  const double f = (xi - x[hi - 1]) / (x[hi] - x[hi - 1]);
  return y[hi - 1] + f * (y[hi] - y[hi - 1]);
}

HousnerErrors housner_errors(const std::vector<double>& t, const std::vector<double>& theta,
                             const reference::HousnerBlock& block, std::size_t count,
                             double hysteresis) {
  HousnerErrors e;
  e.cycles = rocking_cycles(t, theta, hysteresis);
  const RockingCycles& cycles = e.cycles;
  if (cycles.impacts.empty()) return e;
  const double theta0 = std::fabs(theta.front());
  e.first_impact = cycles.impacts[0] / reference::quarter_period(block, theta0) - 1.0;
  const std::vector<double> ref = reference::amplitude_map(block, theta0, static_cast<int>(count));
  for (std::size_t n = 0; n < std::min(count, cycles.amplitudes.size()); ++n) {
    e.amplitude.push_back(cycles.amplitudes[n] / ref[n] - 1.0);
    const double half = cycles.impacts[n + 1] - cycles.impacts[n];
    e.half_cycle.push_back(half / (2.0 * reference::quarter_period(block, ref[n])) - 1.0);
  }
  return e;
}

}  // namespace freestand::validation
