#ifndef FREESTAND_POST_LAUNCHED_BODY_H
#define FREESTAND_POST_LAUNCHED_BODY_H

// A launched body: thrown or tossed onto a fixed table (the cube tosses), not
// standing on its base when the record starts. Its rocking events mean
// nothing (it tumbles); what can be compared is when it touches down, how
// high it bounces, when it comes to rest and where (docs/diagnose.md,
// "Launched bodies"). Plain arrays in, plain structs out.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace freestand {

// True when the body's nominal states an initial velocity or spin (a body
// launched into the record, not released from rest).
bool is_launched(const nlohmann::json& body);

// The body's events from its channels: `uplift` (vertical COM displacement)
// and the six channels' last values.
struct LaunchedEvents {
  std::vector<double> touchdowns;     // s: local minima of uplift, confirmed by a rise of `hysteresis`
  std::vector<double> bounce_heights; // m: highest uplift after each touchdown (until the next) over the final uplift
  double rest_time;                   // s: from then on every channel stays near its final value (below)
};
// `hysteresis` (m): the fall before and rise after a minimum that make it a
// touchdown (noise does not); rest: lengths within `length_band` (m) and
// angles within `angle_band` (rad) of their means over the last 5 samples.
LaunchedEvents launched_events(const std::vector<double>& time, const std::vector<const std::vector<double>*>& lengths,
                               const std::vector<const std::vector<double>*>& angles, const std::vector<double>& uplift,
                               double hysteresis, double length_band, double angle_band);

// The standard deviation of the slope of a least-squares line through n
// samples `step` apart with noise `noise`: sigma sqrt(12 / (n (n^2 - 1))) / step.
// The uncertainty of an initial velocity (or spin) measured from the n
// samples of free flight before the first touchdown.
double flight_rate_sd(double noise, int n, double step);

}  // namespace freestand

#endif
