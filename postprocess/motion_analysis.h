#ifndef FREESTAND_POST_MOTION_ANALYSIS_H
#define FREESTAND_POST_MOTION_ANALYSIS_H

// What one body did, from its six mode channels (../shared/recording-format.md):
// peaks, residual offsets, overturning, a timeline of modes (rest, rock,
// slide, slide-rock, twist, flight), rocking impacts with the ratio of
// angular velocities across them, slip events and separations. Every
// threshold and criterion is defined in docs/postprocessing.md. Plain arrays
// in, plain structs out; no I/O.

#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

#include "signal_tools.h"

namespace freestand::analysis {

using signal::kNaN;

// Channel positions, in the order of channel_names() (src/freestand/body_channels.h).
enum Channel { kRockX, kRockY, kTwist, kSlideX, kSlideY, kUplift, kChannelCount };
using ChannelSeries = std::array<std::vector<double>, kChannelCount>;

struct BodyMotion {
  std::vector<double> time;      // s, strictly increasing
  ChannelSeries channels;        // rad (rock, twist), m (slide, uplift); NaN: lost; empty: not measured
  ChannelSeries rates;           // optional exact rates (rad/s, m/s), e.g. channel_rates(); empty: fitted
  std::vector<double> support_uplift;  // optional (m): vertical displacement of what supports a
                                       // stacked body (top-face centre of the body below); empty: 0
};

// What the analysis needs of the body's shape: the base edges it rocks on.
struct BodyGeometry {
  double half_width_x = kNaN;  // b_x: horizontal distance from the COM to the base edge it rocks on in rock_x (m)
  double half_width_y = kNaN;  // b_y: the same for rock_y (m)
  double com_height = kNaN;    // h: height of the COM above the base face (m)

  bool known(int axis) const;             // b (axis 0: x, 1: y) and h are given
  double slenderness(int axis) const;     // alpha = atan(b / h) (rad)
  double housner_ratio(int axis) const;   // 1 - 1.5 sin^2(alpha): Housner's angular-velocity ratio of a rectangular block
  // Rise of the COM when the body rocks by rock_x, rock_y on its base edges (m);
  // exact for rocking on one edge, to second order in the angles on a corner.
  double rocking_rise(double rock_x, double rock_y) const;
};

struct AnalysisParameters {
  double angle_noise = 1e-4;     // rad, standard deviation of the angle channels' noise (nominal
                                 // sensor_noise.angle); the default is the resolution reported for a noise-free simulation
  double length_noise = 1e-4;    // m, the same for slide and uplift (sensor_noise.length)
  double threshold_sigmas = 4;   // a value or rate counts as non-zero beyond this many standard deviations of its
                                 // noise: white Gaussian noise exceeds 4 sd in 6e-5 of the samples
  double rate_half_window = 0.02;  // s, half width of the straight-line fit that gives rates (5 samples each side at 200 Hz)
  double min_segment = 0.05;     // s, mode segments and slip events shorter than this are merged into a neighbour
  double residual_fraction = 0.1;  // residuals: mean over the last 10 % of the record's duration
  double overturn_margin = 0.1;  // rad, beyond the slenderness angle (or short of lying on a side) that counts as overturned
  double impact_window = 0.05;   // s, longest one-sided fit window for the angular velocity at an impact
};

// Rates of the six channels from the pose and velocities (exact, no
// differentiation). orientation: body frame -> world; omega: angular velocity,
// world (rad/s); com_velocity (m/s, world); support_velocity: velocity of the
// support point (m/s, world), empty: fixed; com_in_body: COM in the body frame
// (origin at the base-face centre, m).
ChannelSeries channel_rates(const std::vector<Eigen::Quaterniond>& orientation,
                            const std::vector<Eigen::Vector3d>& omega,
                            const std::vector<Eigen::Vector3d>& com_velocity,
                            const std::vector<Eigen::Vector3d>& support_velocity,
                            const Eigen::Vector3d& com_in_body);

// Angle (rad) between the body's own vertical axis and the world vertical,
// from rock_x and rock_y (the inverse of rocking_angles(), in [0, pi]).
double tilt(double rock_x, double rock_y);

struct Peak {
  double max = kNaN, t_max = kNaN;  // largest sample and its time (units of the channel, s)
  double min = kNaN, t_min = kNaN;  // smallest (most negative) sample and its time
  double magnitude() const;         // max(|max|, |min|)
};
std::array<Peak, kChannelCount> channel_peaks(const BodyMotion& motion);

struct Residuals {
  double window_start = kNaN;             // s: means are over [window_start, end of record]
  std::array<double, kChannelCount> mean;  // per channel (rad, m); NaN: no finite sample there
};
Residuals residuals(const BodyMotion& motion, const AnalysisParameters& parameters);

struct Overturn {
  bool overturned = false;
  double time = kNaN;     // s, first sample meeting the criterion
  std::string criterion;  // "rock_x beyond alpha + margin and growing", "rock_y ...", "lying on a side"
};

enum class Mode { lost, rest, rock, slide, slide_rock, twist, flight, overturned };
const char* mode_name(Mode mode);

struct ModeSegment {
  Mode mode = Mode::lost;
  double start = kNaN, end = kNaN;  // s
};

// One crossing of the rocking angle through zero (an impact of the base).
struct Impact {
  double time = kNaN;              // s, where the one-sided fits reach zero (mean of both)
  double omega_before = kNaN;      // rad/s, quadratic fit of the angle just before, at `time`
  double omega_after = kNaN;       // rad/s, the same just after
  double omega_before_sd = kNaN;   // rad/s, standard deviation of omega_before from the angle noise
  double omega_after_sd = kNaN;    // rad/s
  double ratio = kNaN;             // |omega_after / omega_before|: Housner's r
  double ratio_sd = kNaN;          // its standard deviation (first-order propagation)
  double amplitude_before = kNaN;  // rad, largest |angle| of the half-cycle ending here
  double amplitude_after = kNaN;   // rad, largest |angle| of the half-cycle starting here
};

struct HalfCycle {  // between two consecutive impacts
  double start = kNaN, end = kNaN;  // s
  double amplitude = kNaN;          // rad, largest |angle| (parabola through the samples around the peak)
};

struct RockingImpacts {
  std::vector<Impact> impacts;
  std::vector<HalfCycle> half_cycles;
  double median_ratio = kNaN;   // median of the finite impact ratios
  double housner_ratio = kNaN;  // 1 - 1.5 sin^2(alpha) when the geometry is known
};
RockingImpacts rocking_impacts(const BodyMotion& motion, int axis, const BodyGeometry& geometry,
                               const AnalysisParameters& parameters);

struct SlipEvent {
  double onset = kNaN, stop = kNaN;  // s
  double slip_x = kNaN, slip_y = kNaN;  // m, slide (rocking part removed) at stop minus at onset
  double peak_speed = kNaN;          // m/s, largest relative sliding speed during the event
};

struct Separation {
  double start = kNaN, end = kNaN;  // s
  double peak_gap = kNaN;           // m, largest uplift beyond what rocking explains
};

struct MotionSummary {
  std::array<Peak, kChannelCount> peaks;
  Residuals residual;
  Overturn overturn;
  std::vector<ModeSegment> modes;
  std::array<RockingImpacts, 2> impacts;  // rock_x, rock_y
  std::vector<SlipEvent> slips;
  std::vector<Separation> separations;
};

// Per-sample evidence of each mode, shared by the timeline and the events.
struct ModeEvidence {
  std::vector<char> rocking, sliding, twisting, flying, known;  // known: some channel finite
  std::vector<double> slip_x, slip_y;  // m: slide with the base-centre motion of rocking removed
  std::vector<double> slip_speed;      // m/s: |d(slip)/dt|
  std::vector<double> excess_uplift;   // m: uplift - support uplift - rocking rise (NaN: unknown geometry)
};
ModeEvidence mode_evidence(const BodyMotion& motion, const BodyGeometry& geometry,
                           const AnalysisParameters& parameters);

Overturn detect_overturn(const BodyMotion& motion, const BodyGeometry& geometry,
                         const AnalysisParameters& parameters);
std::vector<ModeSegment> mode_timeline(const BodyMotion& motion, const ModeEvidence& evidence,
                                       const Overturn& overturn, const AnalysisParameters& parameters);
std::vector<SlipEvent> slip_events(const BodyMotion& motion, const ModeEvidence& evidence,
                                   const AnalysisParameters& parameters);
std::vector<Separation> separations(const BodyMotion& motion, const ModeEvidence& evidence,
                                    const AnalysisParameters& parameters);

// Throws InputError when channel lengths differ from time's, time is not
// strictly increasing or a parameter is out of range. The functions above
// assume a checked motion.
void check_motion(const BodyMotion& motion, const AnalysisParameters& parameters);

// Everything above, after check_motion().
MotionSummary analyse_motion(const BodyMotion& motion, const BodyGeometry& geometry,
                             const AnalysisParameters& parameters = {});

}  // namespace freestand::analysis

#endif
