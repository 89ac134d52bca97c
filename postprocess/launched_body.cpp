#include "launched_body.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace freestand {

bool is_launched(const nlohmann::json& body) {
  for (const char* key : {"velocity", "omega"})
    if (body.contains(key))
      for (const auto& v : body[key])
        if (v.is_number() && v.get<double>() != 0) return true;
  return false;
}

namespace {

constexpr int kFinalSamples = 5;  // samples averaged for the final pose

double final_mean(const std::vector<double>& y) {
  double sum = 0;
  int n = 0;
  for (std::size_t k = y.size() > kFinalSamples ? y.size() - kFinalSamples : 0; k < y.size(); ++k)
    if (std::isfinite(y[k])) sum += y[k], ++n;
  return n ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

// Minima of y confirmed by a fall of `h` before and a rise of `h` after (a
// zigzag with hysteresis: noise below h makes no event), the first after y
// came down by h from where it started or its launch apex; the highest value
// between each minimum and the next, over y's final value (the sampled minimum
// is no reference: the body moves fastest there, up to v x step between samples).
void minima_and_rises(const std::vector<double>& t, const std::vector<double>& y, double h, LaunchedEvents& e) {
  const double rest = final_mean(y);
  double low = std::numeric_limits<double>::infinity(), high = -low, t_low = 0;
  bool falling = false;  // first the start or the launch apex, then down to a touchdown
  for (std::size_t k = 0; k < y.size(); ++k) {
    if (!std::isfinite(y[k])) continue;
    if (falling) {
      if (y[k] < low) low = y[k], t_low = t[k];
      if (y[k] > low + h) {  // confirmed: a touchdown at t_low
        e.touchdowns.push_back(t_low);
        falling = false, high = y[k];
      }
    } else {
      high = std::max(high, y[k]);
      if (y[k] < high - h) {  // coming down: the apex of a bounce (not of the launch)
        if (!e.touchdowns.empty()) e.bounce_heights.push_back(high - rest);
        falling = true, low = y[k], t_low = t[k];
      }
    }
  }
  if (!falling && !e.touchdowns.empty()) e.bounce_heights.push_back(high - rest);
}

// Last sample index at which channel y is farther than `band` from its final value (-1: never).
long last_departure(const std::vector<double>& y, double band) {
  const double end = final_mean(y);
  for (long k = static_cast<long>(y.size()) - 1; k >= 0; --k)
    if (std::isfinite(y[k]) && std::abs(y[k] - end) > band) return k;
  return -1;
}

}  // namespace

LaunchedEvents launched_events(const std::vector<double>& time, const std::vector<const std::vector<double>*>& lengths,
                               const std::vector<const std::vector<double>*>& angles, const std::vector<double>& uplift,
                               double hysteresis, double length_band, double angle_band) {
  LaunchedEvents e;
  minima_and_rises(time, uplift, hysteresis, e);
  long last = -1;
  for (const std::vector<double>* y : lengths) last = std::max(last, last_departure(*y, length_band));
  for (const std::vector<double>* y : angles) last = std::max(last, last_departure(*y, angle_band));
  e.rest_time = time[std::min<std::size_t>(static_cast<std::size_t>(last + 1), time.size() - 1)];
  return e;
}

double flight_rate_sd(double noise, int n, double step) {
  n = std::max(n, 3);  // the first samples always give a slope
  return noise * std::sqrt(12.0 / (n * (static_cast<double>(n) * n - 1))) / step;
}

}  // namespace freestand
