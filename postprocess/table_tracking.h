#ifndef FREESTAND_POST_TABLE_TRACKING_H
#define FREESTAND_POST_TABLE_TRACKING_H

// Did the table do what it was told? A shake table's servo lags its command,
// reads a little high or low and rolls off the high frequencies; a model
// driven by the command then sees a different table than the specimen did.
// This compares a recording's table acceleration (what the table did) with
// the scenario's commanded motion per axis, as a measurement issue, not
// physics (docs/diagnose.md, "Measurement first").

#include <string>
#include <vector>

#include "freestand/shake_table.h"
#include "recording.h"
#include "signal_tools.h"

namespace freestand {

// recorded a(t) ~ gain * commanded a(t - delay) + bias + what is left.
struct TableTracking {
  std::string channel;              // table_ax, table_ay or table_az
  double delay = signal::kNaN;      // s, positive: the table lags its command
  double delay_sd = signal::kNaN;   // s, Cramer-Rao bound of the cross-correlation delay for the noise
  double gain = signal::kNaN;       // least-squares gain after the delay
  double gain_sd = signal::kNaN;
  double correlation = signal::kNaN;
  double left_share = signal::kNaN;   // RMS of what lag, gain and bias leave, over the command's RMS
  double noise_share = signal::kNaN;  // the acceleration noise over the command's RMS
  double noise = signal::kNaN;        // m/s^2, stated (sensor_noise.acceleration) or estimated
  bool noise_stated = false;          // false: estimated from second differences (signal_tools.h)
  bool delay_significant = false, gain_significant = false, left_significant = false;
  std::string text;                   // plain words; empty when the table followed its command
};

// Per translational axis the scenario commands and the recording has table
// acceleration for (recorded or derived): recording time 0 is command time 0,
// offsets up to 0.5 s are searched. Significance at 4 s.d. of the noise.
std::vector<TableTracking> table_tracking(const Recording& recording, const ShakeTable& command);

}  // namespace freestand

#endif
